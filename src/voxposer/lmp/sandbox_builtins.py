"""The builtins sandboxed code runs with: a safe subset, a few guarded, and numpy's imports.

* The safe subset (:data:`SAFE_BUILTINS`): types, math and iteration helpers, the common
  exceptions. No ``open``, ``eval``, ``getattr``, ``type``… (the static check refuses those
  names too, with a clearer message).
* Guarded: ``range`` (size), ``pow`` (as ``**``), ``sorted`` (size and ``n log n`` work),
  ``sum`` (a list or tuple start joins sequences: size), ``iter`` (the two-argument form
  ``iter(callable, sentinel)`` would let a builtin loop forever inside one C call: refused).
* ``__import__``: generated code cannot name it (and ``import`` statements are refused before
  the code runs), but numpy's C code imports its own helpers lazily (``numpy._core._methods``
  the first time ``a.sum()`` runs), and CPython looks that import up in the builtins of the
  running frame — the sandbox's. :func:`trusted_import` lets those through: absolute imports of
  numpy and scipy modules only; anything else raises :class:`voxposer.errors.SandboxError`.
"""

from __future__ import annotations

import builtins
from collections.abc import Callable, Iterable
from typing import Any, Final

from voxposer.errors import SandboxError
from voxposer.lmp.sandbox_limits import Limits
from voxposer.lmp.sandbox_work import sort_work

SAFE_BUILTINS: Final = (
    "abs", "all", "any", "bool", "callable", "chr", "dict", "divmod", "enumerate", "filter",
    "float", "frozenset", "hash", "int", "isinstance", "issubclass", "len", "list", "map",
    "max", "min", "next", "ord", "repr", "reversed", "round", "set", "slice", "str",
    "tuple", "zip", "None", "True", "False", "ArithmeticError", "AssertionError",
    "Exception", "IndexError", "KeyError", "NameError", "TypeError", "ValueError",
    "ZeroDivisionError", "StopIteration",
)
#: Top-level packages whose modules numpy's (and scipy's) own code may import lazily.
TRUSTED_PACKAGES: Final = frozenset({"numpy", "scipy"})


def trusted_import(name: str, globals: Any = None, locals: Any = None,
                   fromlist: Any = (), level: int = 0) -> Any:
    """``__import__`` for library code running under the sandbox's builtins (module docs).

    Raises:
        SandboxError: a relative import, or a module outside :data:`TRUSTED_PACKAGES`.
    """
    root = str(name).partition(".")[0]
    if level != 0 or root not in TRUSTED_PACKAGES:
        raise SandboxError(f"refused: importing {name!r}; generated code cannot import modules "
                           f"(numpy is `np`, scipy's Rotation is `Rotation`)")
    return builtins.__import__(name, globals, locals, fromlist, level)


def make_builtins(limits: Limits, binop: Callable[[str, Any, Any], Any]) -> dict[str, Any]:
    """The ``__builtins__`` dict of one sandbox (module docs)."""

    def safe_range(*args: int) -> range:
        r = range(*args)
        limits.size.check(len(r), "range(...)")
        return r

    def safe_pow(a: Any, b: Any, *mod: Any) -> Any:
        return binop("**", a, b) if not mod else builtins.pow(a, b, *mod)

    def safe_sorted(iterable: Iterable[Any], **kwargs: Any) -> list[Any]:
        items = list(iterable)
        limits.work.check(sort_work(len(items)), "sorted(...)")
        return builtins.sorted(items, **kwargs)

    def safe_sum(iterable: Iterable[Any], start: Any = 0) -> Any:
        if not isinstance(start, list | tuple):
            return builtins.sum(iterable, start)
        items = list(iterable)
        if not all(isinstance(x, type(start)) for x in items):
            return builtins.sum(items, start)  # raises the usual TypeError
        total = len(start) + builtins.sum(len(x) for x in items)
        limits.size.check(total, "sum(..., start) of sequences")
        joined = list(start)
        for x in items:  # linear, where sum() of sequences copies quadratically
            joined.extend(x)
        return joined if isinstance(start, list) else tuple(joined)

    def safe_iter(obj: Any, *sentinel: Any) -> Any:
        if sentinel:
            raise SandboxError("refused: iter(callable, sentinel) (it can loop forever); use a "
                               "for or while loop")
        return builtins.iter(obj)

    names = {name: getattr(builtins, name) for name in SAFE_BUILTINS}
    names.update(range=safe_range, pow=safe_pow, sorted=safe_sorted, sum=safe_sum,
                 iter=safe_iter, print=print, __import__=trusted_import)
    return names
