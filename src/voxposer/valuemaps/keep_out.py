"""Where an avoidance map says "not here": the core the global planner keeps out of.

The paper composes avoidance as a soft cost, so a path that saves length may still cut through
the middle of what it was told to avoid (measured: paths 1–2 cm inside a 10 cm "stay away"
sphere). The planner therefore also treats the core of the avoidance map — voxels whose value is
at least a fraction of the map's maximum — as obstacles, and falls back to the soft cost alone
when that leaves no path (:meth:`voxposer.planning.planner.PathPlanner.plan`). An entity that
starts inside the core may still leave it: only voxels valued above its start's value are kept
out, so the path can always step downhill.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.valuemaps.voxel_ops import pool_max


def keep_out(grid: VoxelGrid, avoid: NDArray[np.floating], start: NDArray[np.float64],
             fraction: float, downsample: int, pooled: NDArray[np.floating] | None = None
             ) -> NDArray[np.bool_]:
    """Coarse voxels the path may not enter, shape ``grid.coarsen(downsample).shape``.

    Args:
        grid: the workspace grid ``avoid`` is written on.
        avoid: the (validated, non-negative) avoidance map, shape ``grid.shape``.
        start: the entity's position [m], shape (3,).
        fraction: voxels valued at least ``fraction`` × the map's maximum are kept out (0: none).
        downsample: fine voxels per planning voxel along each axis.
        pooled: ``avoid``'s block maximum on the planning grid when already made
            (:func:`~voxposer.valuemaps.voxel_ops.pool_max`): a planning voxel is kept out when
            any of its fine voxels reaches the level, i.e. when its maximum does.
    """
    coarse_shape = grid.coarsen(downsample).shape
    top = float(avoid.max()) if avoid.size else 0.0
    if fraction <= 0 or top <= 0:
        return np.zeros(coarse_shape, dtype=bool)
    level = fraction * top
    at_start = float(avoid[tuple(grid.world_to_voxel(start, clip=True))])
    if at_start >= level:  # starting inside: only what is worse than here is kept out
        level = np.nextafter(np.float32(at_start), np.float32(np.inf))
    if pooled is None:
        pooled = pool_max(avoid, downsample)
    return np.asarray(pooled >= level)
