"""6-DoF trajectories: a smoothed path plus the rotation/velocity/gripper maps read along it."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.signal import savgol_filter

from voxposer.errors import InvalidMapError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.valuemaps.maps import check_value_map


class Waypoint(NamedTuple):
    """One trajectory waypoint.

    Attributes:
        position: world position [m], shape (3,).
        quaternion: end-effector orientation (x, y, z, w), shape (4,).
        velocity_scale: speed scale (1 = default speed).
        gripper: gripper command, 1 closed / 0 open.
    """

    position: NDArray[np.float64]
    quaternion: NDArray[np.float64]
    velocity_scale: float
    gripper: float


@dataclass(frozen=True)
class Trajectory:
    """A 6-DoF trajectory of N waypoints, the last one on the affordance target.

    Attributes:
        positions: world positions [m], shape (N, 3).
        quaternions: unit quaternions (x, y, z, w), shape (N, 4).
        velocity_scales: speed scale per waypoint, shape (N,), > 0.
        gripper: gripper command per waypoint, shape (N,), values in {0, 1} (1 = closed).
        voxels: workspace voxel of each waypoint, shape (N, 3).
    """

    positions: NDArray[np.float64]
    quaternions: NDArray[np.float64]
    velocity_scales: NDArray[np.float64]
    gripper: NDArray[np.float64]
    voxels: NDArray[np.int64]

    def __len__(self) -> int:
        return len(self.positions)

    def __getitem__(self, i: int) -> Waypoint:
        return Waypoint(
            self.positions[i],
            self.quaternions[i],
            float(self.velocity_scales[i]),
            float(self.gripper[i]),
        )

    @property
    def length(self) -> float:
        """Path length [m]."""
        return float(np.linalg.norm(np.diff(self.positions, axis=0), axis=1).sum())


def resample(points: NDArray[np.float64], spacing: float) -> NDArray[np.float64]:
    """Points at uniform arc-length ``spacing`` [m] along a polyline, shape (N, 3) → (M, 3).

    The first and last input points are kept exactly.
    """
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    keep = np.concatenate([[True], seg > 1e-9])
    points, seg = points[keep], seg[seg > 1e-9]
    if len(points) < 2:
        return points[:1].copy()
    s = np.concatenate([[0.0], np.cumsum(seg)])
    count = max(int(np.ceil(s[-1] / spacing)), 1)
    t = np.linspace(0.0, s[-1], count + 1)
    return np.stack([np.interp(t, s, points[:, a]) for a in range(3)], axis=1)


def smooth(points: NDArray[np.float64], window: int, polyorder: int) -> NDArray[np.float64]:
    """Savitzky–Golay smoothing of a polyline, shape (N, 3); endpoints stay where they were."""
    n = len(points)
    win = min(window, n if n % 2 else n - 1)
    if win <= polyorder or win < 3:
        return points.copy()
    out = savgol_filter(points, win, polyorder, axis=0, mode="interp")
    out[0], out[-1] = points[0], points[-1]
    return np.asarray(out)


def collides(points: NDArray[np.float64], grid: VoxelGrid, obstacles: NDArray[np.bool_]) -> bool:
    """Whether a polyline [m], shape (N, 3), touches an obstacle voxel (checked every ¼ voxel)."""
    if not obstacles.any():
        return False
    dense = resample(points, float(grid.resolution.min()) / 4.0) if len(points) > 1 else points
    idx = grid.world_to_voxel(dense, clip=True)
    return bool(obstacles[idx[:, 0], idx[:, 1], idx[:, 2]].any())


def _checked(kind: str, value_map: NDArray, grid: VoxelGrid, checked: bool) -> NDArray:
    return value_map if checked else check_value_map(kind, value_map, grid)


def extract_trajectory(
    positions: NDArray[np.float64],
    grid: VoxelGrid,
    *,
    rotation_map: NDArray | None,
    velocity_map: NDArray | None,
    gripper_map: NDArray | None,
    default_quat: NDArray[np.float64],
    default_gripper: float,
    checked: bool = False,
) -> Trajectory:
    """Read the rotation, velocity and gripper maps at each waypoint's voxel.

    A map that is None gives its default everywhere (``default_quat``, speed scale 1,
    ``default_gripper``); maps made by :class:`voxposer.valuemaps.ValueMapAPI` hold those
    defaults wherever the language model did not set a value. ``checked=True`` skips validating
    the maps' shape, dtype and finiteness (the caller has done it).

    Raises:
        InvalidMapError: a map of the wrong shape or with NaN/inf, a zero quaternion, or a
            velocity scale <= 0 on the path.
    """
    vox = grid.world_to_voxel(positions, clip=True)
    ix, iy, iz = vox[:, 0], vox[:, 1], vox[:, 2]
    n = len(positions)
    if rotation_map is None:
        quats = np.tile(np.asarray(default_quat, dtype=np.float64), (n, 1))
    else:
        quats = _checked("rotation", rotation_map, grid, checked)[ix, iy, iz].astype(np.float64)
    norms = np.linalg.norm(quats, axis=1)
    if np.any(norms < 1e-6):
        bad = vox[int(np.argmin(norms))].tolist()
        raise InvalidMapError(
            f"rotation map holds a zero quaternion at voxel {bad}; use unit (x, y, z, w)"
        )
    quats = quats / norms[:, None]
    if velocity_map is None:
        speeds = np.ones(n)
    else:
        speeds = _checked("velocity", velocity_map, grid, checked)[ix, iy, iz].astype(np.float64)
        if np.any(speeds <= 0):
            bad = vox[int(np.argmin(speeds))].tolist()
            raise InvalidMapError(
                f"velocity map has scale {speeds.min():g} at voxel {bad} on the path; scales must be > 0"
            )
    if gripper_map is None:
        grip = np.full(n, float(default_gripper))
    else:
        grip = _checked("gripper", gripper_map, grid, checked)[ix, iy, iz].astype(np.float64)
    return Trajectory(
        positions=positions,
        quaternions=quats,
        velocity_scales=speeds,
        gripper=(grip >= 0.5).astype(np.float64),
        voxels=vox,
    )
