"""The value-map API of the paper (App. A.3), as language model programs call it.

Five kinds of voxel map guide the entity of interest, each an array over the workspace grid
(shape ``grid.shape``, plus a trailing 4 for rotations):

==========  ==============  ==============================================================
kind        empty value     meaning
==========  ==============  ==============================================================
affordance  0               high values attract the entity (the target)
avoidance   0               high values repel the entity
rotation    current quat    end-effector orientation, scalar-last (x, y, z, w), per voxel
velocity    1               speed scale (0.5 = half the default speed)
gripper     current state   1 = closed, 0 = open
==========  ==============  ==============================================================
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.errors import InvalidMapError
from voxposer.geometry.frames import TOP_DOWN_QUAT, pointat2quat
from voxposer.geometry.voxel_grid import VoxelGrid

MAP_KINDS: Final = ("affordance", "avoidance", "rotation", "velocity", "gripper")
MAP_CHANNELS: Final[dict[str, int]] = {
    "affordance": 1,
    "avoidance": 1,
    "rotation": 4,
    "velocity": 1,
    "gripper": 1,
}

def check_value_map(kind: str, value_map: object, grid: VoxelGrid) -> NDArray[np.floating]:
    """Validate a value map of ``kind`` for ``grid`` and return it as a float array.

    Raises:
        InvalidMapError: unknown kind, wrong shape, non-numeric dtype, or NaN/inf values.
    """
    if kind not in MAP_CHANNELS:
        raise InvalidMapError(f"unknown map kind {kind!r}; kinds are: {', '.join(MAP_KINDS)}")
    expected = grid.shape if MAP_CHANNELS[kind] == 1 else (*grid.shape, MAP_CHANNELS[kind])
    if not isinstance(value_map, np.ndarray):
        raise InvalidMapError(
            f"{kind} map must be a numpy array of shape {expected}; got {type(value_map).__name__}"
        )
    if value_map.shape != expected:
        raise InvalidMapError(
            f"{kind} map has shape {value_map.shape}; expected {expected} (the workspace grid)"
        )
    if value_map.dtype.kind not in "biuf":
        raise InvalidMapError(
            f"{kind} map has dtype {value_map.dtype}; expected a bool, integer or float array"
        )
    arr = value_map if value_map.dtype.kind == "f" else value_map.astype(np.float32)
    if not np.all(np.isfinite(arr)):
        bad = np.argwhere(~np.isfinite(arr))[0].tolist()
        raise InvalidMapError(
            f"{kind} map holds NaN or inf (first at voxel {bad}); values must be finite"
        )
    return arr


@dataclass
class ValueMapAPI:
    """Factory of empty value maps and voxel painting, bound to a grid and the robot state.

    Attributes:
        grid: the workspace voxel grid.
        ee_quat: callable returning the current end-effector quaternion (x, y, z, w).
        gripper_state: callable returning the current gripper state (1 closed, 0 open).
    """

    grid: VoxelGrid
    ee_quat: Callable[[], ArrayLike] = lambda: TOP_DOWN_QUAT
    gripper_state: Callable[[], float] = lambda: 0.0

    def get_empty_affordance_map(self) -> NDArray[np.float32]:
        """Zeros, shape ``grid.shape``; set high values where the entity should go."""
        return np.zeros(self.grid.shape, dtype=np.float32)

    def get_empty_avoidance_map(self) -> NDArray[np.float32]:
        """Zeros, shape ``grid.shape``; set high values where the entity should stay away."""
        return np.zeros(self.grid.shape, dtype=np.float32)

    def get_empty_rotation_map(self) -> NDArray[np.float32]:
        """Every voxel = current end-effector quaternion (x, y, z, w); shape ``(*grid.shape, 4)``."""
        q = np.asarray(self.ee_quat(), dtype=np.float32).reshape(4)
        out = np.empty((*self.grid.shape, 4), dtype=np.float32)
        out[...] = q
        return out

    def get_empty_velocity_map(self) -> NDArray[np.float32]:
        """Ones (default speed scale), shape ``grid.shape``."""
        return np.ones(self.grid.shape, dtype=np.float32)

    def get_empty_gripper_map(self) -> NDArray[np.float32]:
        """Current gripper state everywhere (1 closed, 0 open), shape ``grid.shape``."""
        return np.full(self.grid.shape, float(self.gripper_state()), dtype=np.float32)

    def set_voxel_by_radius(
        self, voxel_map: NDArray, voxel_xyz: ArrayLike, radius_cm: float, value: ArrayLike
    ) -> NDArray:
        """Assign ``value`` to every voxel whose centre is within ``radius_cm`` of ``voxel_xyz``.

        The sphere is measured in the world (centimetres converted per axis with the grid
        resolution), so it is round even when voxels are not cubes. The centre voxel is always
        set. ``voxel_map`` is modified in place and returned.

        Args:
            voxel_map: map of shape ``grid.shape`` or ``(*grid.shape, k)``.
            voxel_xyz: centre voxel index, shape (3,); floats are rounded.
            radius_cm: sphere radius [cm], >= 0.
            value: scalar, or shape (k,) for a multi-channel map (e.g. a quaternion).
        """
        if not isinstance(voxel_map, np.ndarray) or voxel_map.shape[:3] != self.grid.shape:
            shape = getattr(voxel_map, "shape", type(voxel_map).__name__)
            raise InvalidMapError(
                f"set_voxel_by_radius needs a map of shape {self.grid.shape} (or with a trailing "
                f"channel axis); got {shape}"
            )
        radius = float(radius_cm)
        if not np.isfinite(radius) or radius < 0:
            raise InvalidMapError(f"radius_cm must be a finite number >= 0; got {radius_cm!r}")
        centre = self.grid.check_voxel(voxel_xyz, "voxel_xyz")
        reach = np.floor(radius / 100.0 / self.grid.resolution).astype(np.int64)
        lo = np.maximum(centre - reach, 0)
        hi = np.minimum(centre + reach + 1, np.asarray(self.grid.shape))
        axes = [
            (np.arange(lo[a], hi[a]) - centre[a]) * self.grid.resolution[a] * 100.0
            for a in range(3)
        ]
        dx, dy, dz = np.meshgrid(*axes, indexing="ij", sparse=True)
        inside = dx**2 + dy**2 + dz**2 <= radius**2 + 1e-9
        block = voxel_map[lo[0] : hi[0], lo[1] : hi[1], lo[2] : hi[2]]
        block[inside] = value
        return voxel_map

    def pointat2quat(self, vector: ArrayLike, fingers: ArrayLike | None = None
                     ) -> NDArray[np.float64]:
        """See :func:`pointat2quat`."""
        return pointat2quat(vector, fingers)

    def cm2index(self, cm: float, direction: str | ArrayLike) -> int | NDArray[np.int64]:
        """See :meth:`VoxelGrid.cm2index`."""
        return self.grid.cm2index(cm, direction)

    def index2cm(self, index: float, direction: str | ArrayLike) -> float:
        """See :meth:`VoxelGrid.index2cm`."""
        return self.grid.index2cm(index, direction)
