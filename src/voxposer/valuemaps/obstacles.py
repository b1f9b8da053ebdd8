"""The planner's obstacles on the planning grid: the scene's (with a margin), the avoidance map's
core, what the caller puts off limits, and, for an object sliding on the table, everything outside
its layer."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.valuemaps.keep_out import keep_out
from voxposer.valuemaps.voxel_ops import ball, clear_sphere, pool_max


def planning_obstacles(
    grid: VoxelGrid, coarse: VoxelGrid, fine_obstacles: NDArray[np.bool_],
    fine_targets: NDArray[np.int64], start: NDArray[np.float64], avoid: NDArray | None,
    layer_z: float | None, *, downsample: int, margin_cm: float, entity_clear_cm: float,
    target_clear_cm: float, keep_out_fraction: float, pooled_avoid: NDArray | None = None,
    off_limits: NDArray[np.bool_] | None = None,
) -> NDArray[np.bool_]:
    """Obstacles on the planning grid, shape ``coarse.shape``: the scene's, pooled and grown by
    the margin (cleared again around the start and the targets); the avoidance map's core
    (:func:`voxposer.valuemaps.keep_out.keep_out`, cleared around the targets); and with
    ``layer_z`` everything outside that layer. Distances in cm; ``downsample`` fine voxels per
    planning voxel; ``keep_out_fraction`` as ``CostMapConfig.avoidance_keep_out``;
    ``pooled_avoid``: ``avoid`` pooled onto the planning grid, when already made;
    ``off_limits``: planning voxels the path may not enter although nothing is there (shape
    ``coarse.shape``; not grown by the margin, cleared around the start and the targets)."""
    f = downsample
    obstacles = pool_max(fine_obstacles, f)
    targets = target_representatives(grid, fine_targets)
    if margin_cm > 0:  # grown on the planning grid (cheap), then cleared again
        radius = margin_cm / 100.0 / coarse.resolution
        obstacles = ndimage.binary_dilation(obstacles, structure=ball(radius))
    if off_limits is not None:
        obstacles = obstacles | off_limits  # pool_max may return the fine mask itself
    if margin_cm > 0 or off_limits is not None:
        clear_sphere(obstacles, coarse, start, entity_clear_cm)
        for target in targets:
            clear_sphere(obstacles, coarse, target, target_clear_cm)
    if avoid is not None and keep_out_fraction > 0:
        core = keep_out(grid, avoid, start, keep_out_fraction, f, pooled_avoid)
        for target in targets:
            clear_sphere(core, coarse, target, target_clear_cm)
        obstacles |= core
    if layer_z is not None:
        kz = int(coarse.world_to_voxel([start[0], start[1], layer_z], clip=True)[2])
        obstacles[:, :, :kz] = True
        obstacles[:, :, kz + 1:] = True
    return obstacles



def target_representatives(
    grid: VoxelGrid, fine_targets: NDArray[np.int64], limit: int = 64
) -> NDArray:
    """World points [m], shape (<= limit, 3), spread over the target voxels, for clearing.

    A large target region (e.g. "the left side of the table") needs no clearing everywhere: the
    target voxels themselves are always free, and clearing around a sample suffices to let the
    path in.
    """
    if len(fine_targets) <= limit:
        return grid.voxel_to_world(fine_targets)
    pick = np.linspace(0, len(fine_targets) - 1, limit).astype(int)
    return grid.voxel_to_world(fine_targets[pick])
