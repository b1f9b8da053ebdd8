"""Indexing guards for sandboxed code: voxel indices stay on the grid, results stay small.

numpy wraps negative indices silently: a target 15 cm below the table (``z = -15``) once became
a voxel at the *top* of the grid, and the robot went there. Generated code indexes value maps with
voxel coordinates, for which a negative number is always a bug.

The rule (checked for every item read ``a[key]`` and write ``a[key] = v`` in generated code):

* **Arrays of ndim >= 3** (value maps, object occupancies, rotation maps): along their first three
  axes (the voxel axes x, y, z), every integer index — a scalar, or each entry of an integer index
  array — must lie in ``[0, shape[axis])``, and slice bounds must be ``>= 0`` (a stop past the end
  is clipped, as usual; negative steps such as ``[::-1]`` are fine). Otherwise
  :class:`voxposer.errors.VoxelIndexError` names the index, the axis and the shape, so the model
  can clip its voxel or fix its offset. Axes after the third (a rotation map's quaternion
  component) keep numpy's rules.
* **Everything else** (positions ``obj.position[-1]``, boxes ``aabb[:-1]``, lists) keeps Python's
  rules: negative indices count from the end, as benign code expects.

Advanced indexing (integer or boolean index arrays) builds a new array whose size is the
broadcast of the index arrays times the remaining axes: ``a[np.zeros(10**6, int)]`` on a
(2, 10**6) array would be 10**12 elements, so item reads are size-checked too.
"""

from __future__ import annotations

from typing import Any, Final

import numpy as np

from voxposer.errors import SandboxError, VoxelIndexError
from voxposer.lmp.sandbox_limits import SizeGuard
from voxposer.lmp.sandbox_work import prod

#: Arrays with at least this many dimensions are indexed by voxel coordinates.
VOXEL_NDIM: Final = 3


def _is_int(value: Any) -> bool:
    if isinstance(value, bool | np.bool_):
        return False
    if isinstance(value, np.ndarray):
        return value.ndim == 0 and value.dtype.kind in "iu"
    return isinstance(value, int | np.integer)


def _normalise(key: Any) -> tuple[Any, ...]:
    """The key as a tuple of parts; lists become arrays (numpy treats them as index arrays)."""
    parts = key if isinstance(key, tuple) else (key,)
    out = []
    for part in parts:
        if isinstance(part, list):
            try:
                part = np.asarray(part)
            except ValueError:
                pass  # ragged: numpy raises its own error when indexing
        out.append(part)
    return tuple(out)


def _span(part: Any) -> int:
    """How many axes a key part consumes (-1: an Ellipsis, which takes the rest)."""
    if part is Ellipsis:
        return -1
    if part is None or isinstance(part, bool | np.bool_):
        return 0
    if isinstance(part, np.ndarray) and part.dtype == bool:
        return part.ndim
    return 1


def axes_of(parts: tuple[Any, ...], ndim: int) -> list[tuple[Any, int, int]]:
    """Each part with the first axis it indexes and how many axes it consumes (for an array
    of ``ndim`` dimensions; an Ellipsis consumes those the other parts leave)."""
    spans = [_span(p) for p in parts]
    rest = max(ndim - sum(s for s in spans if s > 0), 0)
    out, axis = [], 0
    for part, span in zip(parts, spans, strict=True):
        span = rest if span < 0 else span
        out.append((part, axis, span))
        axis += span
    return out


def _voxel_error(index: int, axis: int, shape: tuple[int, ...]) -> VoxelIndexError:
    n = shape[axis]
    wrap = " (numpy would silently wrap it to the far side of the grid)" if index < 0 else ""
    return VoxelIndexError(
        f"voxel index {index} on axis {axis} is outside the grid: the array has shape "
        f"{tuple(shape)}, so indices on that axis must be in [0, {n}){wrap}; clip the voxel "
        f"(e.g. np.clip(v, 0, {n - 1})) or fix the offset's sign")


def _check_part(part: Any, axis: int, shape: tuple[int, ...]) -> None:
    if isinstance(part, slice):
        for bound in (part.start, part.stop):
            if _is_int(bound) and int(bound) < 0:
                raise VoxelIndexError(
                    f"negative slice bound {int(bound)} on voxel axis {axis} of an array of "
                    f"shape {tuple(shape)}: numpy would count it from the far end of the grid; "
                    f"slice bounds of value maps must be >= 0 (clip them, e.g. max(z - 5, 0))")
        return
    if _is_int(part):
        index = int(part)
        if not 0 <= index < shape[axis]:
            raise _voxel_error(index, axis, shape)
        return
    if isinstance(part, np.ndarray) and part.dtype.kind in "iu" and part.size:
        low, high = int(part.min()), int(part.max())
        if low < 0:
            raise _voxel_error(low, axis, shape)
        if high >= shape[axis]:
            raise _voxel_error(high, axis, shape)


def check_voxel_index(array: np.ndarray, key: Any) -> None:
    """Raise :class:`VoxelIndexError` when ``key`` leaves the grid of ``array`` (module rule).

    Arrays of ndim < 3 are not checked.
    """
    if array.ndim < VOXEL_NDIM:
        return
    for part, axis, span in axes_of(_normalise(key), array.ndim):
        if span == 1 and part is not Ellipsis and axis < VOXEL_NDIM:
            _check_part(part, axis, array.shape)


def advanced_index_size(array: np.ndarray, key: Any) -> float:
    """Elements ``array[key]`` creates when ``key`` holds index arrays (0 for a view).

    The index arrays (and scalars beside them) broadcast together; slices and an Ellipsis keep
    their axes.
    """
    parts = _normalise(key)
    if not any(isinstance(p, np.ndarray) and p.ndim > 0 for p in parts):
        return 0.0
    broadcast: list[tuple[int, ...]] = []
    kept = 1
    for part, axis, span in axes_of(parts, array.ndim):
        dims = array.shape[axis:axis + span]
        if isinstance(part, np.ndarray) and part.dtype == bool:
            broadcast.append((int(np.count_nonzero(part)),))
        elif isinstance(part, np.ndarray) or _is_int(part):
            broadcast.append(part.shape if isinstance(part, np.ndarray) else ())
        elif isinstance(part, slice) and dims:
            kept *= len(range(*part.indices(dims[0])))
        elif part is Ellipsis:
            kept *= prod(dims)
    kept *= prod(array.shape[sum(span for _, _, span in axes_of(parts, array.ndim)):])
    try:
        picked = prod(np.broadcast_shapes(*broadcast))
    except ValueError:
        return 0.0  # numpy raises its own error
    return float(picked) * kept


def guarded_getitem(size: SizeGuard) -> Any:
    """``_getitem_(obj, key)`` for generated code: the voxel rule and the size of fancy reads."""

    def getitem(obj: Any, key: Any) -> Any:
        if isinstance(obj, np.ndarray):
            check_voxel_index(obj, key)
            size.check(advanced_index_size(obj, key), "indexing with index arrays a[idx]")
        return obj[key]

    return getitem


class WriteTarget:
    """What ``_write_(obj)`` returns: item writes pass the voxel rule, attribute writes fail.

    Generated code never needs to assign attributes (``a.shape = …``, ``a.flags.writeable = …``),
    so every attribute assignment is refused, naming the attribute.
    """

    __slots__ = ("_obj",)
    _obj: Any

    def __init__(self, obj: Any) -> None:
        object.__setattr__(self, "_obj", obj)

    def __setitem__(self, key: Any, value: Any) -> None:
        if isinstance(self._obj, np.ndarray):
            check_voxel_index(self._obj, key)
        self._obj[key] = value

    def __delitem__(self, key: Any) -> None:
        del self._obj[key]

    def __setattr__(self, name: str, value: Any) -> None:
        raise SandboxError(f"refused: assigning the attribute `.{name}` of a "
                           f"{type(self._obj).__name__}; generated code may assign variables "
                           f"and items (a[i] = v) only")

    def __delattr__(self, name: str) -> None:
        raise SandboxError(f"refused: deleting the attribute `.{name}` of a "
                           f"{type(self._obj).__name__}")
