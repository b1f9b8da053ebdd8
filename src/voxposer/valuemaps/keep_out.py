"""Where an avoidance map says "not here": the core the global planner keeps out of.

The paper composes avoidance as a soft cost, so a path that saves length may still cut through
the middle of what it was told to avoid (measured: paths 1–2 cm inside a 10 cm "stay away"
sphere). The planner therefore also treats the core of the avoidance map — voxels whose value is
at least a fraction of the map's maximum — as obstacles, and falls back to the soft cost alone
when that leaves no path (:meth:`voxposer.planning.planner.PathPlanner.plan`). An entity that
starts inside the core may still leave it, but not go deeper: voxels valued above its start's
value are kept out (the path can always step downhill), and so are the core's voxels deeper
inside it than the start (farther from the core's edge). A flat "11 cm around the block" map
holds the same value everywhere inside, so a pushed block starting 10 cm from the obstacle
would otherwise have nothing kept out and cut to 8 cm of it (dev records, "staying away").
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

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
    # the block maximum holds the map's maximum (its padding is the map's minimum): 8× fewer
    # values to read when it is given
    source = avoid if pooled is None else pooled
    top = float(source.max()) if source.size else 0.0
    if fraction <= 0 or top <= 0:
        return np.zeros(coarse_shape, dtype=bool)
    level = fraction * top
    at_start = float(avoid[tuple(grid.world_to_voxel(start, clip=True))])
    if pooled is None:
        pooled = pool_max(avoid, downsample)
    if at_start < level:
        return np.asarray(pooled >= level)
    # starting inside: what is worse than here, and what lies deeper in the core than here
    worse = pooled >= np.nextafter(np.float32(at_start), np.float32(np.inf))
    coarse = grid.coarsen(downsample)
    return np.asarray(worse | _deeper(np.asarray(pooled >= level),
                                      coarse.world_to_voxel(start, clip=True), coarse.resolution))


def _deeper(core: NDArray[np.bool_], start: NDArray[np.int64], resolution: NDArray[np.float64]
            ) -> NDArray[np.bool_]:
    """The voxels of ``core`` (a coarse mask) farther from its edge than ``start`` (a voxel
    index, inside it); the distance is measured within the core's bounding box grown by a
    voxel (the edge is never farther), in metres along each axis's ``resolution``."""
    found = ndimage.find_objects(core.astype(np.int8))
    out = np.zeros_like(core)
    if not found or found[0] is None:
        return out
    box = tuple(slice(max(s.start - 1, 0), min(s.stop + 1, n))
                for s, n in zip(found[0], core.shape, strict=True))
    depth = ndimage.distance_transform_edt(core[box], sampling=resolution)
    local = tuple(int(i) - b.start for i, b in zip(start, box, strict=True))
    inside = all(0 <= i < d for i, d in zip(local, depth.shape, strict=True))
    if not inside:
        return out
    out[box] = depth > depth[local]
    return out
