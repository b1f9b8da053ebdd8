"""Work limits for sandboxed code: operations whose cost grows faster than their operands.

The size limit bounds what one call may allocate, not how long it runs. A product of two
8,000 x 8,000 matrices has inputs and output within the size limit but takes 5e11 multiply-adds;
inverting such a matrix, sorting a huge array or convolving two long signals is similar. They run
inside one C call, which the time limit (a line tracer) cannot interrupt. :class:`WorkGuard`
estimates the operation count *before* the call and raises :class:`voxposer.errors.SandboxError`
when it exceeds ``SandboxConfig.max_work``.

Checked here: ``@`` / ``np.dot`` / ``np.matmul`` / ``np.inner`` / ``np.tensordot`` /
``np.einsum`` (multiply-adds), ``np.linalg.*`` (about ``m * n * min(m, n)`` per matrix; the
vector norms are linear and unchecked), ``np.sort`` / ``np.argsort`` / ``np.unique`` / ``np.lexsort``
and the set routines (``n log2 n``), ``np.convolve`` / ``np.correlate`` / ``np.polymul``
(``len(a) * len(v)``), ``np.roots`` (an eigenvalue problem), ``np.cov`` / ``np.corrcoef``.
scipy's filters (``scipy.ndimage``) are not exposed to generated code at all.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, Final

import numpy as np

from voxposer.errors import SandboxError


def shape_of(value: Any) -> tuple[int, ...]:
    """The shape numpy would give ``value``, without converting it (no allocation).

    Nested lists are measured along their first elements (numpy refuses ragged ones anyway).
    """
    dims: list[int] = []
    while isinstance(value, list | tuple):
        dims.append(len(value))
        if not value:
            return tuple(dims)
        value = value[0]
    if isinstance(value, np.ndarray | np.generic):
        dims.extend(int(d) for d in value.shape)
    return tuple(dims)


def prod(values: Sequence[int] | tuple[int, ...]) -> int:
    """Product of non-negative ints (1 for an empty sequence)."""
    out = 1
    for v in values:
        out *= max(int(v), 0)
    return out


def elements(value: Any) -> int:
    """Number of elements numpy would make of ``value`` (1 for a scalar)."""
    return prod(shape_of(value))


def sort_work(n: float) -> float:
    """Comparisons of sorting ``n`` items: ``n log2 n``."""
    return float(n) * math.log2(max(float(n), 2.0))


def matmul_work(a: Any, b: Any) -> float:
    """Multiply-adds of ``a @ b``: batch x m x k x n (1-D operands as a row / a column)."""
    return _matmul_work(shape_of(a), shape_of(b))


def _matmul_work(sa: tuple[int, ...], sb: tuple[int, ...]) -> float:
    if not sa or not sb:
        return float(prod(sa) * prod(sb))
    sa = (1, *sa) if len(sa) == 1 else sa
    sb = (*sb, 1) if len(sb) == 1 else sb
    try:
        batch = prod(np.broadcast_shapes(sa[:-2], sb[:-2]))
    except ValueError:
        return 0.0  # numpy raises its own error
    return float(batch) * sa[-2] * sa[-1] * sb[-1]


def matmul_size(a: Any, b: Any) -> float:
    """Elements of the result of ``a @ b`` (0 when the shapes do not match)."""
    sa, sb = shape_of(a), shape_of(b)
    if not sa or not sb:
        return float(max(prod(sa), prod(sb)))
    rows = sa[-2] if len(sa) > 1 else 1
    cols = sb[-1] if len(sb) > 1 else 1
    try:
        batch = prod(np.broadcast_shapes(sa[:-2], sb[:-2]))
    except ValueError:
        return 0.0
    return float(batch) * rows * cols


def dot_work(a: Any, b: Any) -> float:
    """Multiply-adds of ``np.dot(a, b)`` / ``np.inner(a, b)``: size(a) * size(b) / k."""
    sa, sb = shape_of(a), shape_of(b)
    if not sa or not sb:
        return float(prod(sa) * prod(sb))
    return prod(sa) * prod(sb) / max(sa[-1], 1)


def dot_size(a: Any, b: Any) -> float:
    """Elements of the result of ``np.dot(a, b)``: size(a) * size(b) / k**2."""
    sa, sb = shape_of(a), shape_of(b)
    if not sa or not sb:
        return float(max(prod(sa), prod(sb)))
    return prod(sa) * prod(sb) / max(sa[-1], 1) ** 2


def matrix_work(value: Any) -> float:
    """A factorisation of a (batch of) m x n matrix: batch x m x n x min(m, n)."""
    shape = shape_of(value)
    if len(shape) < 2:
        return float(prod(shape))
    m, n = shape[-2], shape[-1]
    return float(prod(shape[:-2])) * m * n * min(m, n)


def _tensordot(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    a, b = args[0], args[1]
    axes = args[2] if len(args) > 2 else kwargs.get("axes", 2)
    sa = shape_of(a)
    if isinstance(axes, int | np.integer):
        contracted = prod(sa[len(sa) - int(axes):]) if int(axes) > 0 else 1
    else:
        picked = np.atleast_1d(np.asarray(axes[0], dtype=np.int64))
        contracted = prod([sa[i] for i in picked if -len(sa) <= i < len(sa)])
    return prod(sa) * elements(b) / max(contracted, 1)


def _einsum(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    """Explicit subscripts: the product of every label's length; else the operands' product."""
    operands = args[1:]
    bound = float(prod([max(elements(op), 1) for op in operands]))
    if not args or not isinstance(args[0], str) or "..." in args[0]:
        return bound
    inputs = args[0].replace(" ", "").split("->")[0].split(",")
    if len(inputs) != len(operands):
        return bound
    dims: dict[str, int] = {}
    for labels, operand in zip(inputs, operands, strict=True):
        shape = shape_of(operand)
        if len(labels) != len(shape):
            return bound
        for label, n in zip(labels, shape, strict=True):
            dims[label] = max(dims.get(label, 1), n)
    return float(prod(list(dims.values()))) * max(len(operands) - 1, 1)


def _norm(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float | None:
    order = args[1] if len(args) > 1 else kwargs.get("ord")
    axis = args[2] if len(args) > 2 else kwargs.get("axis")
    spectral = (isinstance(order, str) and order == "nuc") or (
        isinstance(order, int | float) and abs(order) == 2)
    if spectral and len(shape_of(args[0])) >= 2 and not isinstance(axis, int):
        return matrix_work(args[0])
    return None  # vector norms and the Frobenius norm are linear


def _multi_dot(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    """Left to right (an upper bound of numpy's optimal order)."""
    shapes = [shape_of(a) for a in args[0]]
    total, left = 0.0, shapes[0]
    for right in shapes[1:]:
        total += _matmul_work(left, right)
        left = (left[0] if len(left) > 1 else 1, right[-1] if len(right) > 1 else 1)
    return total


def _first(estimate: Callable[[Any], float]) -> Callable[[tuple[Any, ...], dict[str, Any]], float]:
    return lambda args, kwargs: estimate(args[0])


def _pair(estimate: Callable[[Any, Any], float]) -> Callable[[tuple[Any, ...], dict[str, Any]],
                                                              float]:
    return lambda args, kwargs: estimate(args[0], args[1])


def _sorting(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    return sort_work(sum(elements(a) for a in args[:2]))


def _covariance(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    shape = shape_of(args[0])
    rowvar = kwargs.get("rowvar", True)
    if len(shape) < 2:
        return float(prod(shape))
    variables, samples = (shape[0], shape[1]) if rowvar else (shape[1], shape[0])
    return float(variables) * variables * samples


_Estimate = Callable[[tuple[Any, ...], dict[str, Any]], float | None]
#: np.<name> → estimated operations.
NUMPY_WORK: Final[dict[str, _Estimate]] = {
    "dot": _pair(dot_work), "inner": _pair(dot_work), "matmul": _pair(matmul_work),
    "tensordot": _tensordot, "einsum": _einsum,
    "sort": _first(lambda a: sort_work(elements(a))),
    "argsort": _first(lambda a: sort_work(elements(a))),
    "unique": _first(lambda a: sort_work(elements(a))),
    "sort_complex": _first(lambda a: sort_work(elements(a))),
    "lexsort": _first(lambda keys: elements(keys) * math.log2(max(shape_of(keys)[-1:] + (2,)))),
    "isin": _sorting, "in1d": _sorting, "intersect1d": _sorting, "union1d": _sorting,
    "setdiff1d": _sorting, "setxor1d": _sorting,
    "convolve": _pair(lambda a, v: float(elements(a)) * elements(v)),
    "correlate": _pair(lambda a, v: float(elements(a)) * elements(v)),
    "polymul": _pair(lambda a, v: float(elements(a)) * elements(v)),
    "roots": _first(lambda p: float(elements(p)) ** 3),
    "cov": _covariance, "corrcoef": _covariance,
}
#: np.linalg.<name> → estimated operations (unlisted names: a factorisation of the first argument).
LINALG_WORK: Final[dict[str, _Estimate]] = {
    "norm": _norm, "matrix_norm": _norm, "vector_norm": lambda args, kwargs: None,
    "matmul": _pair(matmul_work), "tensordot": _tensordot, "multi_dot": _multi_dot,
    "outer": _pair(lambda a, b: float(elements(a)) * elements(b)),
    "matrix_power": lambda args, kwargs: matrix_work(args[0]) * math.log2(
        abs(int(args[1] if len(args) > 1 else kwargs.get("n", 1))) + 2),
    "solve": lambda args, kwargs: matrix_work(args[0]) + float(
        elements(args[1]) if len(args) > 1 else 0) * max(shape_of(args[0])[-1:] + (1,)),
    "lstsq": lambda args, kwargs: matrix_work(args[0]) + float(
        elements(args[1]) if len(args) > 1 else 0) * max(shape_of(args[0])[-1:] + (1,)),
    "cross": lambda args, kwargs: None, "diagonal": lambda args, kwargs: None,
    "trace": lambda args, kwargs: None, "matrix_transpose": lambda args, kwargs: None,
    "vecdot": lambda args, kwargs: None,
}


class WorkGuard:
    """Checks estimated operation counts against ``max_work`` (multiply-adds / comparisons)."""

    def __init__(self, max_work: int) -> None:
        self.max_work = int(max_work)

    def check(self, work: float, what: str) -> None:
        """Raise :class:`SandboxError` when ``work`` operations would exceed the limit."""
        if not math.isfinite(work) or work > self.max_work:
            raise SandboxError(
                f"work limit: {what} would take about {work:.3g} operations; the sandbox allows "
                f"at most {self.max_work:,} per call (a value map has 1,000,000 voxels: work on "
                f"the voxels you need, not on all pairs of them)"
            )

    def check_call(self, path: str, name: str, args: tuple[Any, ...],
                   kwargs: dict[str, Any]) -> None:
        """Estimate the work of ``<path>.<name>(*args, **kwargs)`` before it is called."""
        estimate: _Estimate | None
        if path == "np.linalg":
            estimate = LINALG_WORK.get(name, _first(matrix_work))
        elif path == "np":
            estimate = NUMPY_WORK.get(name)
        else:
            estimate = None
        if estimate is None or not args:
            return
        try:
            work = estimate(args, kwargs)
        except (IndexError, TypeError, ValueError):
            return  # malformed arguments: numpy raises its own, clearer error
        if work is not None:
            self.check(work, f"{path}.{name}(...)")
