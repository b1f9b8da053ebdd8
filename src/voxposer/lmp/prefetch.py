"""The value-map programs a composer program will ask for, asked of the backend together.

A composer program such as ::

    affordance_map = get_affordance_map('a point 10cm above the blue block')
    avoidance_map = get_avoidance_map('10cm around the green block')

makes its map LMP calls one after another while it runs, each a full generation. Their queries
are literal strings, known as soon as the composer's code is: :func:`map_queries` reads them
from the code, and the runtime sends their first requests in one
:meth:`~voxposer.lmp.backends.base.LLMBackend.complete_many` call before running it (a backend
that decodes several sequences at once generates them together). :class:`Prefetched` holds the
responses until the calls ask for them; a call whose query is computed at run time, or a retry,
goes to the model as before.
"""

from __future__ import annotations

import ast

from voxposer.lmp.backends.base import LLMResponse
from voxposer.lmp.registry import MAP_LMPS


def map_queries(code: str) -> list[tuple[str, str]]:
    """(map LMP, query) of every call in ``code`` to a value-map LMP with one string literal
    argument, in the order they appear, each once; [] for code that does not parse."""
    try:
        tree = ast.parse(code)
    except SyntaxError:
        return []
    calls = sorted(
        (node.lineno, node.col_offset, node.func.id, node.args[0].value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
        and node.func.id in MAP_LMPS and len(node.args) == 1 and not node.keywords
        and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str))
    found: list[tuple[str, str]] = []
    for *_, lmp, query in calls:
        if (lmp, query) not in found:
            found.append((lmp, query))
    return found


class Prefetched:
    """First-attempt responses asked ahead, by (LMP, query); each is taken once."""

    def __init__(self) -> None:
        self._responses: dict[tuple[str, str], LLMResponse] = {}

    def __contains__(self, key: tuple[str, str]) -> bool:
        return key in self._responses

    def put(self, lmp: str, query: str, response: LLMResponse) -> None:
        """Hold ``response`` for the first call of ``lmp(query)``."""
        self._responses[(lmp, query)] = response

    def take(self, lmp: str, query: str) -> LLMResponse | None:
        """The held response of ``lmp(query)`` (removed), or None."""
        return self._responses.pop((lmp, query), None)
