"""Checks run before the allocating methods of objects sandboxed code holds.

:class:`voxposer.lmp.sandbox_attrs.AttributePolicy` returns such a method as a
:class:`CheckedMethod`: before each call, its check estimates the size (and, for super-linear
methods, the work) of the result from the object and the arguments, and raises
:class:`voxposer.errors.SandboxError` through the sandbox's :class:`~voxposer.lmp.sandbox_limits.
Limits` when it is too large. A check that must consume an iterator (``str.join``,
``list.extend``) returns the materialised arguments, which the call then uses.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from voxposer.lmp.sandbox_limits import Limits
from voxposer.lmp.sandbox_sizes import as_shape, dtype_width, random_size
from voxposer.lmp.sandbox_work import dot_size, dot_work, elements, prod, sort_work

#: A check run before a method: (limits, the object, args, kwargs, "what") → replacement args
#: (when it had to consume an iterator) or None.
Checker = Callable[[Limits, Any, tuple[Any, ...], dict[str, Any], str], tuple[Any, ...] | None]


class CheckedMethod:
    """A bound method whose result size (and work) is checked before each call."""

    __slots__ = ("_check", "_limits", "_method", "_obj", "_what")

    def __init__(self, what: str, method: Callable[..., Any], check: Checker, limits: Limits,
                 obj: Any) -> None:
        self._what, self._method, self._check = what, method, check
        self._limits, self._obj = limits, obj

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        replaced = self._check(self._limits, self._obj, args, kwargs, self._what)
        return self._method(*(args if replaced is None else replaced), **kwargs)

    def __repr__(self) -> str:
        return f"<sandboxed {self._what}>"


def check_same_size(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    limits.size.check(float(np.size(obj)), what)


def check_astype(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    """``astype``: the same elements, counted in 8-byte units of the new dtype (a 64M-element
    array as ``complex256`` is 2 GB, four times the limit's bytes)."""
    dtype = kwargs.get("dtype", args[0] if args else None)
    limits.size.check(float(np.size(obj)) * dtype_width(dtype), what)


def check_new_shape(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    """``reshape`` / ``resize``: the product of the new shape (``-1``: the same size)."""
    shape = kwargs.get("shape", kwargs.get("new_shape", args[0] if len(args) == 1 else args))
    dims = as_shape(shape) or []
    limits.size.check(float(np.size(obj)) if -1 in dims else float(prod(dims)), what)


def check_with_self(estimate: Callable[[tuple, dict], float]) -> Checker:
    """An np.<name> size estimate applied to ``obj.<name>(...)`` (``obj`` first)."""

    def check(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
        limits.size.check(estimate((obj, *args), kwargs), what)

    return check


def check_dot(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    limits.size.check(dot_size(obj, args[0]), what)
    limits.work.check(dot_work(obj, args[0]), what)


def check_sorting(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    limits.size.check(float(np.size(obj)), what)
    limits.work.check(sort_work(float(np.size(obj))), what)


def check_nonzero(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    limits.size.check(float(np.size(obj)) * max(np.ndim(obj), 1), what)


def check_random(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    limits.size.check(random_size(what.rsplit(".", 1)[-1], args, kwargs), what)


def check_first_elements(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    limits.size.check(float(elements(args[0])) if args else 0.0, what)


def check_outer(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    limits.size.check(float(prod([elements(a) for a in args])), what)


def check_rotation_count(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    num = args[0] if args else kwargs.get("num")
    limits.size.check(4.0 * int(num) if isinstance(num, int | np.integer) else 4.0, what)


def _materialise(value: Any) -> Any:
    return value if isinstance(value, list | tuple | str | dict | set | frozenset | range) \
        else list(value)


def check_extend(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> tuple:
    items = _materialise(args[0])
    limits.size.check(float(len(obj) + len(items)), what)
    return (items,)


def check_join(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> tuple:
    items = _materialise(args[0])
    total = sum(len(x) for x in items if isinstance(x, str)) + len(obj) * max(len(items) - 1, 0)
    limits.size.check(float(total), what)
    return (items,)


def check_replace(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    old, new = str(args[0]), str(args[1])
    count = obj.count(old)
    limit = args[2] if len(args) > 2 else kwargs.get("count", -1)
    if isinstance(limit, int) and limit >= 0:
        count = min(count, limit)
    limits.size.check(float(len(obj) + count * max(len(new) - len(old), 0)), what)


def check_list_sort(limits: Limits, obj: Any, args: tuple, kwargs: dict, what: str) -> None:
    limits.work.check(sort_work(len(obj)), what)
