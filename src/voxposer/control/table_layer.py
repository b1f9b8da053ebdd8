"""A pushed object slides on the table: its targets are at its own height.

The object planner keeps such an object's path in the layer of its centre (``layer_z`` of
:meth:`voxposer.planning.planner.PathPlanner.plan`; without it, paths rising over what the block
should go around were measured, and the pushes then drove it into the obstacle); its affordance
is brought into that layer here: a block on the table reaches a place only at its own height.
Its path also keeps within the arm's pushing reach (:func:`beyond_push_reach`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid


def onto_layer(grid: VoxelGrid, affordance: NDArray, height: float) -> NDArray:
    """``affordance`` (shape ``grid.shape``) with every column's highest value moved into the
    layer of ``height`` [m] and zeros elsewhere."""
    kz = int(np.clip(grid.world_to_voxel([0.0, 0.0, height], clip=True)[2], 0, grid.shape[2] - 1))
    aff = np.asarray(affordance)
    out = np.zeros_like(aff)
    out[:, :, kz] = aff.max(axis=2)
    return out


def beyond_push_reach(grid: VoxelGrid, base: NDArray[np.float64], reach_m: tuple[float, float]
                      ) -> NDArray[np.bool_]:
    """Voxels (shape ``grid.shape``) nearer than ``reach_m[0]`` or farther than ``reach_m[1]``
    [m] across the table from the robot's ``base`` [m], shape (3,): a block pushed there can no
    longer be pushed every way. Beyond the far radius the hand, standing beyond the block to
    push it back, is out of the arm's reach (dev records: a detour took a block 0.79 m out and
    every push back toward the base was refused); within the near one the hand, standing
    between the block and the base to push it away, is crowded against the arm's own column
    (dev records: pushes there took 5-8 s of simulated time each, and the block ran out of
    time 8 cm from its place).
    """
    centres = [grid.bounds_min[a] + (np.arange(grid.shape[a]) + 0.5) * grid.resolution[a]
               for a in range(2)]
    dx, dy = centres[0] - base[0], centres[1] - base[1]
    r2 = dx[:, None] ** 2 + dy[None, :] ** 2
    out = (r2 < reach_m[0] ** 2) | (r2 > reach_m[1] ** 2)
    return np.broadcast_to(out[:, :, None], grid.shape)
