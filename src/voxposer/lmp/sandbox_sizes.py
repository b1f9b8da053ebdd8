"""Result sizes of numpy calls, estimated from their arguments before the call.

:meth:`voxposer.lmp.sandbox_limits.SizeGuard.check_call` compares these estimates with
``SandboxConfig.max_elements``. Each estimate is the number of elements the call would create
(an upper bound where the exact count needs the call itself), computed without converting or
copying the arguments:

* every function: its ``shape`` / ``size`` / ``num`` / ``bins``… keywords; constructors with a
  shape (``zeros``, ``full``, ``empty``, ``np.ndarray``…): their shape argument, found by
  position (:data:`SHAPE_ARGS`; an int elsewhere is data, ``np.max([90, 95, 99, 80])``);
* functions that multiply sizes (``arange``, ``linspace``, ``tile``, ``repeat``, ``meshgrid``,
  ``outer``, ``kron``, ``pad``, ``eye``, ``diag``, ``bincount``, ``tri*_indices``, ``take``,
  ``cov``, ``vander``, ``histogramdd``) and those that join arrays (``concatenate``, ``stack``,
  ``array`` of a list of arrays…): their own formula below;
* ufuncs and broadcasting functions (``np.add``, ``np.where``, ``np.clip``…): the broadcast shape
  of their operands, as for operators;
* ``np.random.*`` (and a Generator's methods): their ``size`` argument, found by position;
  ``np.fft.*``: the padded length ``n`` / ``s``; ``np.linalg.svd`` / ``qr``: the full factors.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

import numpy as np

from voxposer.lmp.sandbox_work import dot_size, elements, matmul_size, prod, shape_of

_SIZE_WORDS: Final = ("shape", "size", "num", "reps", "repeats", "N", "M", "new_shape", "count",
                      "bins", "width", "padding")
#: np.<name> → the positions of its shape-like arguments (the generic rule; size keywords count
#: for every function). Other positional ints are data: ``np.max([90, 95, 99, 80])`` is fine.
SHAPE_ARGS: Final[dict[str, tuple[int, ...]]] = {
    "zeros": (0,), "ones": (0,), "empty": (0,), "full": (0,), "broadcast_to": (1,),
    "fromfunction": (1,), "fromiter": (2,), "hanning": (0,), "hamming": (0,), "blackman": (0,),
    "bartlett": (0,), "kaiser": (0,), "histogram": (1,), "histogram_bin_edges": (1,),
    "binary_repr": (1,), "base_repr": (2,), "unpackbits": (2,), "ndarray": (0,),
    "recarray": (0,),
}
#: np.random function / Generator method → position of its ``size`` argument ("*": every
#: positional argument is a dimension; None: creates nothing sized).
RANDOM_SIZE_ARG: Final[dict[str, int | str | None]] = {
    "random": 0, "random_sample": 0, "sample": 0, "ranf": 0, "standard_normal": 0,
    "standard_exponential": 0, "bytes": 0, "permutation": 0, "rand": "*", "randn": "*",
    "uniform": 2, "normal": 2, "randint": 2, "integers": 2, "binomial": 2, "lognormal": 2,
    "laplace": 2, "logistic": 2, "gamma": 2, "beta": 2, "choice": 1, "exponential": 1,
    "poisson": 1, "rayleigh": 1, "geometric": 1, "triangular": 3, "multivariate_normal": 2,
    "seed": None, "default_rng": None, "shuffle": None, "permuted": None, "get_state": None,
    "set_state": None, "spawn": None,
}
_BROADCASTING: Final = frozenset({"where", "clip", "isclose", "allclose", "broadcast_arrays",
                                  "piecewise", "heaviside", "copyto"})
_JOINING: Final = frozenset({"concatenate", "stack", "vstack", "hstack", "dstack",
                             "column_stack", "row_stack", "concat"})
_CONVERTING: Final = frozenset({"array", "asarray", "asanyarray", "ascontiguousarray",
                                "asfortranarray", "copy", "atleast_1d", "atleast_2d",
                                "atleast_3d", "nan_to_num", "asarray_chkfinite", "matrix"})


def as_shape(value: Any) -> list[int] | None:
    """A shape-like argument (an int or a sequence of ints) as a list, or None."""
    if isinstance(value, bool | np.bool_):
        return None
    if isinstance(value, int | np.integer):
        return [int(value)]
    if isinstance(value, np.ndarray) and value.dtype.kind in "iu" and value.size <= 64 \
            and value.ndim <= 1:
        return [int(v) for v in value.reshape(-1)]
    if isinstance(value, tuple | list) and value and all(
        isinstance(v, int | np.integer) and not isinstance(v, bool) for v in value
    ):
        return [int(v) for v in value]
    return None


def _arg(args: tuple[Any, ...], kwargs: dict[str, Any], index: int, key: str,
         default: Any = None) -> Any:
    return args[index] if len(args) > index else kwargs.get(key, default)


def broadcast_elements(*operands: Any) -> float:
    """Elements of the broadcast of ``operands`` (0 when they do not broadcast)."""
    try:
        return float(prod(np.broadcast_shapes(*(shape_of(o) for o in operands))))
    except ValueError:
        return 0.0


def _arange(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    nums = [float(a) for a in args if isinstance(a, int | float | np.number)]
    nums += [float(kwargs[k]) for k in ("start", "stop", "step") if k in kwargs]
    if len(nums) == 1:
        return abs(nums[0])
    if len(nums) >= 2:
        step = nums[2] if len(nums) > 2 else 1.0
        return 0.0 if step == 0 else abs((nums[1] - nums[0]) / step)
    return 0.0


def _repeat(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    reps = _arg(args, kwargs, 1, "repeats", 1)
    return elements(args[0]) * max(int(np.max(reps)) if np.size(reps) else 0, 1)


def _tile(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    reps = _arg(args, kwargs, 1, "reps", 1)
    return elements(args[0]) * max(prod([int(r) for r in np.atleast_1d(reps)]), 1)


def _pad(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    width = _arg(args, kwargs, 1, "pad_width", 0)
    widest = int(np.max(np.abs(np.asarray(width, dtype=np.int64)))) if np.size(width) else 0
    return float(prod([d + 2 * widest for d in shape_of(args[0])]))


def _eye(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    n = int(args[0])
    m = _arg(args, kwargs, 1, "M")
    return float(n) * (int(m) if isinstance(m, int | np.integer) else n)


def _diag(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    shape = shape_of(args[0])
    k = abs(int(_arg(args, kwargs, 1, "k", 0)))
    return float(shape[0] + k) ** 2 if len(shape) == 1 else float(prod(shape))


def _bincount(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    values = np.asarray(args[0])
    top = int(np.max(values)) + 1 if values.size and values.dtype.kind in "iu" else 0
    return float(max(top, int(_arg(args, kwargs, 2, "minlength", 0) or 0)))


def _tri_indices(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    n = int(args[0])
    m = _arg(args, kwargs, 2, "m")
    return 2.0 * n * (int(m) if m is not None else n)


def _take(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    axis = _arg(args, kwargs, 2, "axis")
    shape = shape_of(args[0])
    if axis is None or not shape:
        return float(elements(args[1]))
    return elements(args[1]) * prod(shape) / max(shape[int(axis)], 1)


def _covariance(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    shape = shape_of(args[0])
    if len(shape) < 2:
        return 1.0
    variables = shape[0] if kwargs.get("rowvar", True) else shape[1]
    return float(variables) ** 2


def _spaced(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    num = int(_arg(args, kwargs, 2, "num", 50))
    return num * max(broadcast_elements(args[0], _arg(args, kwargs, 1, "stop", 0)), 1.0)


def _histogram_nd(args: tuple[Any, ...], kwargs: dict[str, Any], where: int) -> float:
    bins = _arg(args, kwargs, where, "bins", 10)
    dims = shape_of(args[0])
    count = 2 if where == 2 else (dims[-1] if len(dims) > 1 else 1)
    if isinstance(bins, int | np.integer):
        return float(int(bins) + 1) ** count
    return float(prod([int(b) if isinstance(b, int | np.integer) else elements(b)
                       for b in bins]))


def _block(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    total, stack = 0, [args[0]]
    while stack:
        item = stack.pop()
        if isinstance(item, list | tuple):
            stack.extend(item)
        else:
            total += elements(item)
    return float(total)


_Estimate = Callable[[tuple[Any, ...], dict[str, Any]], float]
#: np.<name> → estimated result elements (the names the generic rule would get wrong).
NUMPY_SIZES: Final[dict[str, _Estimate]] = {
    "arange": _arange, "repeat": _repeat, "tile": _tile, "pad": _pad,
    "meshgrid": lambda args, kwargs: float(prod([elements(a) for a in args])) * max(len(args), 1),
    "ix_": lambda args, kwargs: float(prod([elements(a) for a in args])) * max(len(args), 1),
    "outer": lambda args, kwargs: float(elements(args[0])) * elements(args[1]),
    "matmul": lambda args, kwargs: matmul_size(args[0], args[1]),
    "dot": lambda args, kwargs: dot_size(args[0], args[1]),
    "inner": lambda args, kwargs: dot_size(args[0], args[1]),
    "kron": lambda args, kwargs: float(elements(args[0])) * elements(args[1]),
    "indices": lambda args, kwargs: float(prod(as_shape(args[0]) or [0])) * len(
        as_shape(args[0]) or [0]),
    "eye": _eye, "identity": _eye, "tri": _eye, "diag": _diag, "diagflat": _diag,
    "bincount": _bincount, "tril_indices": _tri_indices, "triu_indices": _tri_indices,
    "mask_indices": lambda args, kwargs: 2.0 * int(args[0]) ** 2,
    "diag_indices": lambda args, kwargs: float(int(args[0])) * int(_arg(args, kwargs, 1, "ndim", 2)),
    "nonzero": lambda args, kwargs: float(elements(args[0])) * max(len(shape_of(args[0])), 1),
    "argwhere": lambda args, kwargs: float(elements(args[0])) * max(len(shape_of(args[0])), 1),
    "take": _take, "cov": _covariance, "corrcoef": _covariance,
    "histogram2d": lambda args, kwargs: _histogram_nd(args, kwargs, 2),
    "histogramdd": lambda args, kwargs: _histogram_nd(args, kwargs, 1),
    "vander": lambda args, kwargs: float(elements(args[0])) * int(
        _arg(args, kwargs, 1, "N", None) or elements(args[0])),
    "polyfit": lambda args, kwargs: float(elements(args[0])) * (int(args[2]) + 1),
    "linspace": _spaced, "logspace": _spaced, "geomspace": _spaced, "block": _block,
    "append": lambda args, kwargs: float(elements(args[0]) + elements(args[1])),
    **dict.fromkeys(_JOINING, lambda args, kwargs: float(sum(elements(a) for a in args[0]))),
    **dict.fromkeys(_CONVERTING, lambda args, kwargs: float(elements(args[0]))),
}


def _generic(args: tuple[Any, ...], kwargs: dict[str, Any],
             positions: tuple[int, ...] | None = None) -> float:
    """The largest shape among the arguments at ``positions`` (None: all) and the size
    keywords."""
    picked = list(args) if positions is None else [args[i] for i in positions if i < len(args)]
    sizes = [0.0]
    for value in picked + [kwargs[k] for k in _SIZE_WORDS if k in kwargs]:
        shape = as_shape(value)
        if shape is not None:
            sizes.append(float(prod(shape)))
    return max(sizes)


def random_size(name: str, args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    """Elements a np.random function or Generator method ``name`` would draw."""
    where = RANDOM_SIZE_ARG.get(name, -1)
    if where is None:
        return 0.0
    if where == -1:
        return _generic(args, kwargs)
    if where == "*":
        return float(prod([int(a) for a in args if isinstance(a, int | np.integer)]))
    size = args[int(where)] if len(args) > int(where) else kwargs.get("size")
    if name == "permutation" and not isinstance(size, int | np.integer):
        return float(elements(size))
    shape = as_shape(size)
    return float(prod(shape)) if shape is not None else 0.0


def _fft(args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    shape = shape_of(args[0]) if args else ()
    padded = _arg(args, kwargs, 1, "n", None)
    padded = _arg(args, kwargs, 1, "s", None) if padded is None else padded
    lengths = as_shape(padded)
    if lengths is None or not shape:
        return float(prod(shape))
    kept = shape[: max(len(shape) - len(lengths), 0)]
    return float(prod(kept)) * prod(lengths)


def _linalg(name: str, args: tuple[Any, ...], kwargs: dict[str, Any]) -> float:
    shape = shape_of(args[0]) if args else ()
    if len(shape) < 2:
        return 0.0
    m, n = shape[-2], shape[-1]
    batch = prod(shape[:-2])
    if name == "svd" and _arg(args, kwargs, 1, "full_matrices", True):
        return float(batch) * (m * m + n * n)
    if name == "qr" and _arg(args, kwargs, 1, "mode", "reduced") == "complete":
        return float(batch) * m * m
    return 0.0


def estimate_call_size(path: str, name: str, func: Any, args: tuple[Any, ...],
                       kwargs: dict[str, Any]) -> float:
    """Elements ``<path>.<name>(*args, **kwargs)`` would create (0 when nothing is known).

    Raises:
        TypeError, ValueError, IndexError: malformed arguments (the caller lets numpy report).
    """
    if path == "np.random":
        return random_size(name, args, kwargs)
    if path == "np.fft":
        return _fft(args, kwargs)
    if path == "np.linalg":
        return _linalg(name, args, kwargs)
    if name == "where" and len(args) == 1:
        return NUMPY_SIZES["nonzero"](args, kwargs)
    estimate = NUMPY_SIZES.get(name)
    if estimate is not None:
        return estimate(args, kwargs) if args else 0.0
    if isinstance(func, np.ufunc) or name in _BROADCASTING:
        return broadcast_elements(*args)
    return _generic(args, kwargs, SHAPE_ARGS.get(name, ()))


def dtype_width(dtype: Any) -> float:
    """How many 8-byte elements one element of ``dtype`` counts as (at least 1; 1 when
    ``dtype`` is None or not a dtype)."""
    if dtype is None:
        return 1.0
    try:
        return max(1.0, np.dtype(dtype).itemsize / 8.0)
    except (TypeError, ValueError):
        return 1.0
