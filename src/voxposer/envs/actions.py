"""Checking end-effector commands before they reach the controller.

Every check raises :class:`~voxposer.errors.InvalidActionError` naming the offending value and
the allowed range; nothing is clipped silently.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.errors import InvalidActionError
from voxposer.geometry.voxel_grid import VoxelGrid


@dataclass(frozen=True)
class PoseCommand:
    """A checked end-effector command.

    Attributes:
        position: target position [m], shape (3,), inside the workspace.
        quat_xyzw: unit target orientation, scalar-last (x, y, z, w).
        gripper: 1.0 closed, 0.0 open, or None to leave the gripper as it is.
        speed_scale: multiplier of the default end-effector speed (> 0).
    """

    position: NDArray[np.float64]
    quat_xyzw: NDArray[np.float64]
    gripper: float | None
    speed_scale: float


def check_command(
    position: ArrayLike,
    quat_xyzw: ArrayLike,
    gripper: float | None,
    speed_scale: float,
    *,
    grid: VoxelGrid,
    max_speed_scale: float,
) -> PoseCommand:
    """Validate and normalise a pose command (see :class:`PoseCommand`)."""
    pos = np.asarray(position, dtype=np.float64).reshape(-1)
    if pos.shape != (3,) or not np.all(np.isfinite(pos)):
        raise InvalidActionError(f"position must be 3 finite numbers [m]; got {position!r}")
    if not bool(grid.contains(pos)):
        raise InvalidActionError(
            f"position {np.round(pos, 4).tolist()} m is outside the workspace "
            f"[{grid.bounds_min.tolist()}, {grid.bounds_max.tolist()}] m"
        )
    quat = np.asarray(quat_xyzw, dtype=np.float64).reshape(-1)
    if quat.shape != (4,) or not np.all(np.isfinite(quat)):
        raise InvalidActionError(f"quaternion must be 4 finite numbers (x, y, z, w); got {quat_xyzw!r}")
    norm = float(np.linalg.norm(quat))
    if not 0.5 <= norm <= 1.5:
        raise InvalidActionError(
            f"quaternion (x, y, z, w) must have unit norm; got norm {norm:.4g} for {quat.tolist()}"
        )
    grip: float | None = None
    if gripper is not None:
        grip = float(gripper)
        if not (np.isfinite(grip) and 0.0 <= grip <= 1.0):
            raise InvalidActionError(f"gripper must be in [0, 1] (1 closed, 0 open); got {gripper!r}")
    scale = float(speed_scale)
    if not (np.isfinite(scale) and 0.0 < scale <= max_speed_scale):
        raise InvalidActionError(f"speed_scale must be in (0, {max_speed_scale}]; got {speed_scale!r}")
    return PoseCommand(pos, quat / norm, grip, scale)
