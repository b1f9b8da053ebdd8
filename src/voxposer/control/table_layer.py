"""A pushed object slides on the table: its targets are at its own height.

The object planner keeps such an object's path in the layer of its centre (``layer_z`` of
:meth:`voxposer.planning.planner.PathPlanner.plan`; without it, paths rising over what the block
should go around were measured, and the pushes then drove it into the obstacle); its affordance
is brought into that layer here: a block on the table reaches a place only at its own height.
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
