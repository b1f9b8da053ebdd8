"""The voxel workspace: every world↔voxel conversion lives here.

Axis convention (used everywhere in voxposer): world frame in metres, right-handed, z up.
Seen by a person standing at the front of the table facing the robot:

====================  =========
word                  direction
====================  =========
front                 +x
back / behind         −x
right                 +y
left                  −y
above / top / over    +z
below / under         −z
====================  =========

Voxel ``(i, j, k)`` indexes axes ``(x, y, z)``. The workspace box ``[bounds_min, bounds_max]`` is
cut into ``shape`` equal cells of size ``resolution = (bounds_max - bounds_min) / shape`` metres.
Voxel ``i`` covers ``[min + i*res, min + (i+1)*res)`` and its centre is ``min + (i + 0.5)*res``.
Rounding rule: a point maps to the cell containing it (``floor``); a point exactly on the upper
bound belongs to the last cell. So ``voxel_to_world(world_to_voxel(p))`` is within half a voxel
of ``p`` on every axis.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Final

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.errors import GridError, OutOfWorkspaceError

AXIS_NAMES: Final = ("x", "y", "z")

#: Named directions accepted by :meth:`VoxelGrid.cm2index` and friends (unit vectors).
NAMED_DIRECTIONS: Final[dict[str, tuple[float, float, float]]] = {
    "x": (1.0, 0.0, 0.0),
    "+x": (1.0, 0.0, 0.0),
    "-x": (-1.0, 0.0, 0.0),
    "y": (0.0, 1.0, 0.0),
    "+y": (0.0, 1.0, 0.0),
    "-y": (0.0, -1.0, 0.0),
    "z": (0.0, 0.0, 1.0),
    "+z": (0.0, 0.0, 1.0),
    "-z": (0.0, 0.0, -1.0),
    "front": (1.0, 0.0, 0.0),
    "back": (-1.0, 0.0, 0.0),
    "behind": (-1.0, 0.0, 0.0),
    "right": (0.0, 1.0, 0.0),
    "left": (0.0, -1.0, 0.0),
    "up": (0.0, 0.0, 1.0),
    "above": (0.0, 0.0, 1.0),
    "top": (0.0, 0.0, 1.0),
    "down": (0.0, 0.0, -1.0),
    "below": (0.0, 0.0, -1.0),
    "under": (0.0, 0.0, -1.0),
}


def _vec3(value: ArrayLike, name: str) -> NDArray[np.float64]:
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != (3,):
        raise GridError(f"{name} must have 3 entries (x, y, z); got shape {arr.shape}: {value!r}")
    if not np.all(np.isfinite(arr)):
        raise GridError(f"{name} must be finite; got {arr.tolist()}")
    return arr


def unit_direction(direction: str | ArrayLike) -> NDArray[np.float64]:
    """A unit vector, shape (3,), from a named direction (``"x"``, ``"-y"``, ``"left"``…) or a vector."""
    if isinstance(direction, str):
        key = direction.strip().lower()
        if key not in NAMED_DIRECTIONS:
            raise GridError(
                f"unknown direction {direction!r}; use a 3-vector or one of: "
                + ", ".join(NAMED_DIRECTIONS)
            )
        return np.array(NAMED_DIRECTIONS[key])
    vec = np.asarray(direction, dtype=np.float64).reshape(-1)
    if vec.shape != (3,) or not np.all(np.isfinite(vec)):
        raise GridError(f"direction must be a finite 3-vector or an axis name; got {direction!r}")
    norm = float(np.linalg.norm(vec))
    if norm < 1e-12:
        raise GridError(f"direction must be non-zero; got {vec.tolist()}")
    return vec / norm


@dataclass(frozen=True)
class VoxelGrid:
    """An axis-aligned box of the world cut into voxels.

    Attributes:
        bounds_min: lower corner of the workspace [m], shape (3,).
        bounds_max: upper corner of the workspace [m], shape (3,); strictly above ``bounds_min``.
        shape: number of voxels along (x, y, z); the paper uses 100×100×100.
    """

    bounds_min: NDArray[np.float64]
    bounds_max: NDArray[np.float64]
    shape: tuple[int, int, int] = (100, 100, 100)
    resolution: NDArray[np.float64] = field(init=False, repr=False, compare=False)

    def __init__(
        self,
        bounds_min: ArrayLike,
        bounds_max: ArrayLike,
        shape: tuple[int, int, int] | ArrayLike = (100, 100, 100),
    ) -> None:
        lo = _vec3(bounds_min, "bounds_min")
        hi = _vec3(bounds_max, "bounds_max")
        if np.any(lo >= hi):
            bad = [AXIS_NAMES[i] for i in range(3) if lo[i] >= hi[i]]
            raise GridError(
                f"bounds_min must be below bounds_max on every axis; axis {', '.join(bad)} has "
                f"min {lo.tolist()} >= max {hi.tolist()}"
            )
        shp = np.asarray(shape).reshape(-1)
        if shp.shape != (3,) or not np.all(np.equal(np.mod(shp, 1), 0)) or np.any(shp < 1):
            raise GridError(f"shape must be 3 positive integers; got {shape!r}")
        lo.flags.writeable = False
        hi.flags.writeable = False
        res = (hi - lo) / shp.astype(np.float64)
        res.flags.writeable = False
        object.__setattr__(self, "bounds_min", lo)
        object.__setattr__(self, "bounds_max", hi)
        object.__setattr__(self, "shape", (int(shp[0]), int(shp[1]), int(shp[2])))
        object.__setattr__(self, "resolution", res)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, VoxelGrid):
            return NotImplemented
        return (
            self.shape == other.shape
            and np.array_equal(self.bounds_min, other.bounds_min)
            and np.array_equal(self.bounds_max, other.bounds_max)
        )

    def __hash__(self) -> int:
        return hash((self.shape, self.bounds_min.tobytes(), self.bounds_max.tobytes()))

    # ------------------------------------------------------------------ queries
    @property
    def size(self) -> int:
        """Total number of voxels."""
        return self.shape[0] * self.shape[1] * self.shape[2]

    def contains(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Whether world points [m], shape (..., 3), lie inside the (closed) workspace box."""
        p = np.asarray(points, dtype=np.float64)
        return np.all((p >= self.bounds_min) & (p <= self.bounds_max), axis=-1)

    def voxel_in_grid(self, voxels: ArrayLike) -> NDArray[np.bool_]:
        """Whether integer voxel indices, shape (..., 3), are valid for this grid."""
        v = np.asarray(voxels)
        return np.all((v >= 0) & (v < np.asarray(self.shape)), axis=-1)

    # -------------------------------------------------------------- conversion
    def world_to_voxel(self, points: ArrayLike, *, clip: bool = False) -> NDArray[np.int64]:
        """Voxel indices, shape (..., 3), of the cells containing world points [m], shape (..., 3).

        Args:
            points: world positions in metres.
            clip: if False (default) a point outside the workspace raises
                :class:`OutOfWorkspaceError`; if True it is moved to the nearest boundary cell.
        """
        p = np.asarray(points, dtype=np.float64)
        if p.shape[-1:] != (3,):
            raise OutOfWorkspaceError(f"points must have shape (..., 3); got {p.shape}")
        if not np.all(np.isfinite(p)):
            raise OutOfWorkspaceError("points must be finite; got NaN or inf")
        if not clip:
            inside = self.contains(p)
            if not np.all(inside):
                first = p.reshape(-1, 3)[~inside.reshape(-1)][0]
                raise OutOfWorkspaceError(
                    f"point {np.round(first, 4).tolist()} m is outside the workspace "
                    f"[{self.bounds_min.tolist()}, {self.bounds_max.tolist()}] m"
                )
        idx = np.floor((p - self.bounds_min) / self.resolution).astype(np.int64)
        return np.clip(idx, 0, np.asarray(self.shape) - 1)

    def voxel_to_world(self, voxels: ArrayLike) -> NDArray[np.float64]:
        """World positions [m], shape (..., 3), of voxel centres; fractional indices interpolate."""
        v = np.asarray(voxels, dtype=np.float64)
        if v.shape[-1:] != (3,):
            raise OutOfWorkspaceError(f"voxels must have shape (..., 3); got {v.shape}")
        return self.bounds_min + (v + 0.5) * self.resolution

    def check_voxel(self, voxel: ArrayLike, name: str = "voxel") -> NDArray[np.int64]:
        """Round a (possibly float) voxel index, shape (3,), and check it is inside the grid."""
        v = np.asarray(voxel, dtype=np.float64).reshape(-1)
        if v.shape != (3,) or not np.all(np.isfinite(v)):
            raise OutOfWorkspaceError(f"{name} must be 3 finite numbers (x, y, z); got {voxel!r}")
        idx = np.rint(v).astype(np.int64)
        if not self.voxel_in_grid(idx):
            raise OutOfWorkspaceError(
                f"{name} {idx.tolist()} is outside the grid; valid indices are 0..{self.shape[0] - 1}"
                f", 0..{self.shape[1] - 1}, 0..{self.shape[2] - 1} along x, y, z"
            )
        return idx

    # ------------------------------------------------------- distances (App. A.3)
    def cm2index(self, cm: float, direction: str | ArrayLike) -> int | NDArray[np.int64]:
        """Voxel displacement for an offset of ``cm`` centimetres along ``direction``.

        Args:
            cm: distance in centimetres (may be negative).
            direction: an axis name (``"x"``, ``"-y"``, ``"left"``…) or a 3-vector.

        Returns:
            For a plain axis name (``"x"``, ``"y"``, ``"z"``): a signed int number of voxels along
            that axis. Otherwise an int array of shape (3,): the displacement in voxels, rounded
            to the nearest voxel on each axis.
        """
        u = unit_direction(direction)
        disp = (float(cm) / 100.0) * u / self.resolution
        if isinstance(direction, str) and direction.strip().lower() in AXIS_NAMES:
            axis = AXIS_NAMES.index(direction.strip().lower())
            return int(np.rint(disp[axis]))
        return np.rint(disp).astype(np.int64)

    def index2cm(self, index: float, direction: str | ArrayLike) -> float:
        """Centimetres spanned by ``index`` voxels along ``direction`` (inverse of :meth:`cm2index`).

        The voxel-space displacement along a world direction ``u`` for ``c`` cm is
        ``c/100 * u / resolution``; this returns the ``c`` whose displacement has length ``index``.
        """
        u = unit_direction(direction)
        per_metre = float(np.linalg.norm(u / self.resolution))  # voxels per metre along u
        return 100.0 * float(index) / per_metre

    # --------------------------------------------------------------- occupancy
    def points_to_occupancy(self, points: ArrayLike) -> NDArray[np.bool_]:
        """Occupancy grid, shape ``self.shape``, of world points [m], shape (N, 3).

        Points outside the workspace are dropped (a point cloud is cropped, not clipped).
        """
        p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
        occ = np.zeros(self.shape, dtype=bool)
        _mark_points(p, np.asarray(self.bounds_min, dtype=np.float64),
                     np.asarray(self.resolution, dtype=np.float64),
                     np.asarray(self.shape, dtype=np.int64), occ)
        return occ

    def flat_voxels(self, points: ArrayLike) -> NDArray[np.int64]:
        """Flat (C-order) indices into an array of shape ``self.shape``, shape (N,), of the
        voxels of world points [m], shape (N, 3), each moved to the nearest boundary cell when
        outside: ``np.ravel_multi_index`` of ``world_to_voxel(points, clip=True)``, in one
        compiled pass without temporaries.

        Raises:
            OutOfWorkspaceError: a point is not finite.
        """
        p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
        out = np.empty(len(p), dtype=np.int64)
        if not _flat_voxels(p, np.asarray(self.bounds_min, dtype=np.float64),
                            np.asarray(self.resolution, dtype=np.float64),
                            np.asarray(self.shape, dtype=np.int64), out):
            raise OutOfWorkspaceError("points must be finite; got NaN or inf")
        return out

    def coarsen(self, factor: int) -> VoxelGrid:
        """The same box cut into ``ceil(shape / factor)`` voxels (used for fast planning).

        When ``shape`` is not a multiple of ``factor`` the box grows on the upper side so each
        coarse voxel covers exactly ``factor`` fine voxels per axis.
        """
        if factor < 1:
            raise GridError(f"coarsening factor must be >= 1; got {factor}")
        shp = np.asarray(self.shape)
        coarse = -(-shp // factor)
        hi = self.bounds_min + coarse * factor * self.resolution
        return VoxelGrid(self.bounds_min, hi, tuple(int(c) for c in coarse))


@numba.njit(cache=True, nogil=True)
def _mark_points(points: np.ndarray, lo: np.ndarray, res: np.ndarray, shape: np.ndarray,
                 occ: np.ndarray) -> None:  # pragma: no cover - compiled
    """Set ``occ`` True at the voxel of every point (N, 3) [m] inside the box (the upper bound
    belongs to the last cell; NaN points are dropped): one pass, no temporaries."""
    for n in range(points.shape[0]):
        sx = (points[n, 0] - lo[0]) / res[0]
        sy = (points[n, 1] - lo[1]) / res[1]
        sz = (points[n, 2] - lo[2]) / res[2]
        if (sx >= 0.0 and sx <= shape[0] and sy >= 0.0 and sy <= shape[1]  # False for NaN
                and sz >= 0.0 and sz <= shape[2]):
            occ[min(int(sx), shape[0] - 1), min(int(sy), shape[1] - 1),
                min(int(sz), shape[2] - 1)] = True


@numba.njit(cache=True, nogil=True)
def _flat_voxels(points: np.ndarray, lo: np.ndarray, res: np.ndarray, shape: np.ndarray,
                 out: np.ndarray) -> bool:  # pragma: no cover - compiled
    """Write the clipped voxel's flat index of every point (N, 3) [m] into ``out`` (N,), as
    ``floor((p - lo) / res)`` clipped to ``[0, shape - 1]`` per axis; False (stopping) at the
    first point that is not finite."""
    for n in range(points.shape[0]):
        flat = 0
        for a in range(3):
            s = (points[n, a] - lo[a]) / res[a]
            if not np.isfinite(s):
                return False
            k = int(np.floor(s))
            k = min(max(k, 0), shape[a] - 1)
            flat = flat * shape[a] + k
        out[n] = flat
    return True
