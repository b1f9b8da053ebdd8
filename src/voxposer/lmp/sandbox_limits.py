"""Size limits for sandboxed code: the size guard and guarded arithmetic.

Generated code may allocate arrays (``np.zeros((10**5,) * 3)``) or sequences (``[0] * 10**10``)
large enough to take the machine down before any time limit fires, because the work happens
inside one C call. These guards compute the size of the result *before* the call and raise
:class:`voxposer.errors.SandboxError` naming the construct when it exceeds the limit.

* :class:`SizeGuard` checks element counts; :meth:`SizeGuard.check_call` estimates numpy calls
  (:mod:`voxposer.lmp.sandbox_sizes`). numpy reaches generated code through
  :class:`voxposer.lmp.sandbox_numpy.NumpyProxy`, methods of the objects it returns through
  :mod:`voxposer.lmp.sandbox_attrs`, indexing through :mod:`voxposer.lmp.sandbox_index`.
* :class:`Limits` bundles it with the :class:`~voxposer.lmp.sandbox_work.WorkGuard`.
* :func:`make_binop_guard` checks ``a * b``, ``a + b`` on sequences, ``a ** b``, ``a << b``,
  array broadcasting and ``a @ b`` (size and work).
"""

from __future__ import annotations

import math
import operator
import re
from collections.abc import Callable
from typing import Any, Final, NamedTuple

import numpy as np

from voxposer.errors import SandboxError
from voxposer.lmp.sandbox_sizes import dtype_width, estimate_call_size
from voxposer.lmp.sandbox_work import WorkGuard, matmul_size, matmul_work, prod, shape_of


class SizeGuard:
    """Checks result sizes against ``max_elements`` (array elements / sequence items)."""

    def __init__(self, max_elements: int) -> None:
        self.max_elements = int(max_elements)

    def check(self, count: float, what: str) -> None:
        """Raise :class:`SandboxError` when ``count`` elements would exceed the limit."""
        if not math.isfinite(count) or count > self.max_elements:
            raise SandboxError(
                f"size limit: {what} would create {count:.3g} elements; the sandbox allows at "
                f"most {self.max_elements:,} (the value maps have 1,000,000 voxels)"
            )

    def check_call(self, name: str, args: tuple[Any, ...], kwargs: dict[str, Any],
                   path: str = "np", func: Any = None) -> None:
        """Estimate the size of ``<path>.<name>(*args, **kwargs)`` before calling it."""
        try:
            count = estimate_call_size(path, name, func, args, kwargs)
        except (IndexError, TypeError, ValueError, OverflowError):
            return  # malformed arguments: the call itself raises numpy's clearer error
        # a dtype wider than 8 bytes counts as several elements (the limit is on memory)
        self.check(count * dtype_width(kwargs.get("dtype")), f"{path}.{name}(...)")


class Limits(NamedTuple):
    """The size and work guards of one sandbox."""

    size: SizeGuard
    work: WorkGuard


_BINOPS: Final[dict[str, Callable[[Any, Any], Any]]] = {
    "+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv,
    "//": operator.floordiv, "%": operator.mod, "**": operator.pow, "<<": operator.lshift,
    ">>": operator.rshift, "&": operator.and_, "|": operator.or_, "^": operator.xor,
    "@": operator.matmul,
}
_SEQUENCES: Final = (str, bytes, list, tuple)
#: One printf-style conversion: (width, precision, type); ``*`` takes the next argument.
_PERCENT: Final = re.compile(r"%(?:\([^)]*\))?[-+ #0]*(\*|\d+)?(?:\.(\*|\d+))?[hlL]?([a-zA-Z%])")


def percent_padding(fmt: str, args: Any) -> int:
    """Characters the widths and precisions of ``fmt % args`` may add (``'%*d' % (10**9, 1)``)."""
    values = list(args) if isinstance(args, tuple) else [args]
    total, used = 0, 0
    for width, precision, kind in _PERCENT.findall(fmt):
        for part in (width, precision):
            if part == "*":
                n = values[used] if used < len(values) else 0
                used += 1
                total += abs(n) if isinstance(n, int) else 0
            elif part:
                total += int(part)
        used += kind != "%"
    return total


def _check_operands(limits: Limits, op: str, a: Any, b: Any) -> None:
    """Raise when ``a <op> b`` would exceed a limit."""
    if op == "*" and (isinstance(a, _SEQUENCES) or isinstance(b, _SEQUENCES)):
        seq, n = (a, b) if isinstance(a, _SEQUENCES) else (b, a)
        if isinstance(n, int):
            limits.size.check(len(seq) * max(n, 0), f"repeating a {type(seq).__name__}")
    elif op == "%" and isinstance(a, str):
        limits.size.check(len(a) + percent_padding(a, b), "formatting a str with %")
    elif op == "+" and isinstance(a, _SEQUENCES) and isinstance(b, _SEQUENCES):
        limits.size.check(len(a) + len(b), f"joining two {type(a).__name__}s")
    elif op in ("**", "<<") and isinstance(a, int) and isinstance(b, int) and b > 0:
        bits = b if op == "<<" else b * max(abs(a), 2).bit_length()
        if bits > 65_536:
            raise SandboxError(
                f"size limit: {a} {op} {b} would be an integer of about {bits:,} bits"
            )
    elif op == "@":
        limits.size.check(matmul_size(a, b), "the matrix product a @ b")
        limits.work.check(matmul_work(a, b), "the matrix product a @ b")
    elif isinstance(a, np.ndarray | np.generic) or isinstance(b, np.ndarray | np.generic):
        try:
            shape = np.broadcast_shapes(shape_of(a), shape_of(b))
        except ValueError:
            shape = ()
        limits.size.check(prod(shape), f"the array expression a {op} b")


def make_binop_guard(limits: Limits) -> Callable[[str, Any, Any], Any]:
    """``binop(op, a, b)``: ``a <op> b`` after checking the size (and work) of its result.

    Checks sequence repetition and concatenation (``[0] * n``, ``"x" * n``, ``a + a``), the
    padding of ``"%*d" % (n, x)``, huge integer powers and shifts, numpy broadcasting (``a[:, None] * b[None, :]``) and matrix
    products (their result size and multiply-adds).
    """

    def binop(op: str, a: Any, b: Any) -> Any:
        op = op.rstrip("=") if op.endswith("=") and op not in ("==",) else op
        func = _BINOPS.get(op)
        if func is None:
            raise SandboxError(f"refused: unknown operator {op!r}; allowed: "
                               f"{' '.join(_BINOPS)}")
        _check_operands(limits, op, a, b)
        return func(a, b)

    return binop
