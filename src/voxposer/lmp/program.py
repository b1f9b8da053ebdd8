"""Re-evaluable programs: cached generated code that runs again on a fresh observation.

When composer code calls ``get_affordance_map("...")`` it receives a :class:`ValueMapProgram`
rather than an array. The LLM was asked once (and the code checked once); every later call of the
program re-runs the cached code against the scene as it is *now* — objects that moved move the
target — without a new LLM call (paper footnote 3).
"""

from __future__ import annotations

from typing import Any, Protocol


class Replayer(Protocol):
    """What a program needs of the runtime that made it (an :class:`~voxposer.lmp.runtime.
    LMPRuntime`): re-running cached code on the scene as it is now."""

    def replay(self, lmp: str, query: str) -> Any: ...

_OBJECT_FIELDS = frozenset({"name", "position", "aabb", "occupancy", "normal", "position_world",
                            "aabb_world"})


class ValueMapProgram:
    """Cached code of ``lmp(query)``; calling it returns the current result.

    Attributes:
        lmp: the LMP's name ("get_affordance_map").
        query: the query it answers.
        code: the accepted generated code.
        evaluations: how many times it has been re-run through this object.
    """

    def __init__(self, runtime: Replayer, lmp: str, query: str, code: str) -> None:
        self._runtime = runtime
        self.lmp = lmp
        self.query = query
        self.code = code
        self.evaluations = 0

    def __call__(self) -> Any:
        """Re-run the code on the current observation (no LLM call) and return its result.

        Raises:
            LMPFailedError: the cached code fails on the current observation.
        """
        self.evaluations += 1
        return self._runtime.replay(self.lmp, self.query)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.lmp}({self.query!r}))"


class ObjectProgram(ValueMapProgram):
    """A re-evaluable ``parse_query_obj`` result; reading a field evaluates it now
    (``movable.position``, ``movable["position"]``)."""

    def __getattr__(self, name: str) -> Any:
        if name in _OBJECT_FIELDS:
            return getattr(self(), name)
        raise AttributeError(name)

    def __getitem__(self, key: str) -> Any:
        return self()[key]
