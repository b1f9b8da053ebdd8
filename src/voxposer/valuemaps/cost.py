"""From value maps to the planner's cost map (paper Sec. 4 "Value Map Composition", "Motion Planner").

The affordance map becomes a Euclidean distance transform to its target voxels, the avoidance
map is smoothed with a Gaussian; each is normalised to [0, 1] and they are summed with weights
2 and 1. Scene occupancy (from a point cloud) marks obstacles, cleared near the target and
around the moving entity so neither the start nor the goal sits inside one.

For speed the cost map is built on a coarser copy of the grid (``downsample`` fine voxels per
coarse voxel and axis; 2 by default, i.e. 50³ for the paper's 100³): affordance targets and
obstacles are pooled conservatively (a coarse voxel is a target / an obstacle if any of its fine
voxels is), the avoidance map by its maximum, and the Gaussian's sigma is scaled to match.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.config_checks import require_non_negative, require_positive
from voxposer.errors import ConfigError, EmptyAffordanceError, OutOfWorkspaceError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.valuemaps.maps import check_value_map
from voxposer.valuemaps.obstacles import planning_obstacles, target_representatives
from voxposer.valuemaps.voxel_ops import (
    clear_sphere,
    distance_to,
    nonzero_voxels,
    normalise,
    pool_max,
    smooth_zero_padded,
)


@dataclass(frozen=True)
class CostMapConfig:
    """Parameters of cost-map composition; defaults follow the paper and its release.

    Attributes:
        affordance_weight: weight of the normalised affordance distance term (paper: 2).
        avoidance_weight: weight of the normalised smoothed avoidance term (paper: 1).
        avoidance_sigma: Gaussian sigma for the avoidance map [fine voxels] (release: 10).
        gaussian_truncate: the Gaussian kernel is cut at this many sigmas.
        target_threshold: voxels with affordance >= threshold * max are targets (1 = the maxima).
        target_clear_radius_cm: obstacles within this radius of a target are cleared [cm].
        entity_clear_radius_cm: obstacles within this radius of the entity's start are cleared [cm].
        obstacle_margin_cm: obstacles are grown by this margin [cm] on the planning grid (0 =
            points as observed; pooling onto the planning grid already rounds them outwards).
        downsample: fine voxels per coarse planning voxel along each axis (1 = full resolution).
        obstacles_as_avoidance: also add scene obstacles to the avoidance map before smoothing,
            as the paper's release did (its greedy planner had no hard obstacles).
        avoidance_keep_out: voxels whose avoidance value is at least this fraction of the
            map's maximum are also obstacles (:mod:`voxposer.valuemaps.keep_out`; the planner
            falls back to the soft cost alone when that leaves no path); 0 = the paper's soft
            cost only.
    """

    affordance_weight: float = 2.0
    avoidance_weight: float = 1.0
    avoidance_sigma: float = 10.0
    gaussian_truncate: float = 3.0
    target_threshold: float = 1.0
    target_clear_radius_cm: float = 5.0
    entity_clear_radius_cm: float = 5.0
    obstacle_margin_cm: float = 0.0
    downsample: int = 2
    obstacles_as_avoidance: bool = False
    avoidance_keep_out: float = 0.5

    def __post_init__(self) -> None:
        require_non_negative(self, "avoidance_weight", "avoidance_sigma", "target_clear_radius_cm",
                             "entity_clear_radius_cm", "obstacle_margin_cm", "avoidance_keep_out")
        require_positive(self, "affordance_weight")
        if not 0 < self.target_threshold <= 1:
            raise ConfigError(
                f"CostMapConfig.target_threshold must be in (0, 1]; got {self.target_threshold!r}"
            )
        if not 0 < self.gaussian_truncate <= 8:
            raise ConfigError(
                f"CostMapConfig.gaussian_truncate must be in (0, 8]; got {self.gaussian_truncate!r}"
            )
        if not isinstance(self.downsample, int) or not 1 <= self.downsample <= 8:
            raise ConfigError(
                f"CostMapConfig.downsample must be an int in 1..8; got {self.downsample!r}"
            )


@dataclass(frozen=True)
class CostMap:
    """The planner's objective on the (coarse) planning grid.

    Attributes:
        grid: the planning grid (the workspace grid coarsened by ``config.downsample``).
        fine_grid: the workspace grid the value maps were written on.
        cost: combined cost, shape ``grid.shape``, float32, in [0, w_aff + w_avoid].
        affordance_cost: normalised distance to the nearest target, shape ``grid.shape``, in [0, 1].
        avoidance_cost: normalised smoothed avoidance, shape ``grid.shape``, in [0, 1].
        target_distance: distance to the nearest target [coarse voxels], shape ``grid.shape``.
        target_mask: coarse target voxels, shape ``grid.shape``.
        obstacles: coarse obstacle voxels after clearing, shape ``grid.shape``.
        off_limits: coarse voxels put off limits by the caller (part of ``obstacles``), shape
            ``grid.shape``, or None.
        fine_obstacles: fine obstacle voxels after clearing (without the margin), shape
            ``fine_grid.shape``.
        fine_targets: fine target voxel indices, shape (T, 3).
        start: the entity's start position [m], shape (3,).
    """

    grid: VoxelGrid
    fine_grid: VoxelGrid
    cost: NDArray[np.float32]
    affordance_cost: NDArray[np.float32]
    avoidance_cost: NDArray[np.float32]
    target_distance: NDArray[np.float32]
    target_mask: NDArray[np.bool_]
    obstacles: NDArray[np.bool_]
    fine_obstacles: NDArray[np.bool_]
    fine_targets: NDArray[np.int64]
    start: NDArray[np.float64]
    config: CostMapConfig
    off_limits: NDArray[np.bool_] | None = None


def compose_cost_map(
    grid: VoxelGrid,
    affordance_map: NDArray,
    start: ArrayLike,
    avoidance_map: NDArray | None = None,
    occupancy: NDArray[np.bool_] | None = None,
    entity_occupancy: NDArray[np.bool_] | None = None,
    config: CostMapConfig | None = None,
    *,
    layer_z: float | None = None,
    off_limits: NDArray[np.bool_] | None = None,
) -> CostMap:
    """Build the planner's cost map from value maps and scene occupancy.

    Args:
        grid: the workspace grid the maps are written on.
        affordance_map: shape ``grid.shape``; high values attract.
        start: the entity's current position [m], shape (3,); must be inside the workspace.
        avoidance_map: shape ``grid.shape``; high values repel. None = nothing to avoid.
        occupancy: scene obstacle voxels, shape ``grid.shape`` (e.g. from
            :meth:`VoxelGrid.points_to_occupancy`). None = free space.
        entity_occupancy: voxels of the moving entity itself, removed from ``occupancy``.
        config: parameters; paper defaults when None.
        layer_z: if given, every planning voxel outside the layer at this height [m] is an
            obstacle (an object sliding on the table stays at its height).
        off_limits: voxels the path may not enter although the scene is free there (e.g. where
            a pushed object could no longer be pushed back), shape ``grid.shape``; a planning
            voxel is off limits when any of its voxels is. None = none.

    Raises:
        InvalidMapError: a map with the wrong shape, dtype or NaN/inf values.
        EmptyAffordanceError: no affordance voxel is positive.
        OutOfWorkspaceError: ``start`` is outside the workspace.
    """
    cfg = config or CostMapConfig()
    aff = check_value_map("affordance", affordance_map, grid)
    start_m = np.asarray(start, dtype=np.float64).reshape(-1)
    if start_m.shape != (3,) or not np.all(np.isfinite(start_m)):
        raise OutOfWorkspaceError(f"start must be a finite 3-vector [m]; got {start!r}")
    grid.world_to_voxel(start_m)  # raises when outside the workspace
    fine_targets = _fine_targets(aff, cfg.target_threshold)

    f = cfg.downsample
    coarse = grid.coarsen(f)
    target_mask = np.zeros(coarse.shape, dtype=bool)
    ct = fine_targets // f
    target_mask[ct[:, 0], ct[:, 1], ct[:, 2]] = True

    # Affordance: distance to the nearest target, normalised.
    target_distance = distance_to(target_mask, np.unique(ct, axis=0))
    affordance_cost = normalise(target_distance.copy())

    fine_obstacles = _scene_obstacles(grid, occupancy, entity_occupancy, start_m, fine_targets, cfg)
    avoid = None if avoidance_map is None else _non_negative(
        check_value_map("avoidance", avoidance_map, grid))
    pooled = None if avoid is None else pool_max(avoid, f)
    avoidance_cost = _avoidance_cost(coarse.shape, pooled, fine_obstacles, cfg)
    cost = cfg.affordance_weight * affordance_cost
    if cfg.avoidance_weight > 0:
        cost += cfg.avoidance_weight * avoidance_cost

    limits = None if off_limits is None else pool_max(_off_limits(off_limits, grid), f)
    obstacles = planning_obstacles(
        grid, coarse, fine_obstacles, fine_targets, start_m, avoid, layer_z,
        downsample=f, margin_cm=cfg.obstacle_margin_cm, entity_clear_cm=cfg.entity_clear_radius_cm,
        target_clear_cm=cfg.target_clear_radius_cm, keep_out_fraction=cfg.avoidance_keep_out,
        pooled_avoid=pooled, off_limits=limits)
    obstacles &= ~target_mask
    return CostMap(
        grid=coarse,
        fine_grid=grid,
        cost=cost.astype(np.float32, copy=False),
        affordance_cost=affordance_cost,
        avoidance_cost=avoidance_cost,
        target_distance=target_distance,
        target_mask=target_mask,
        obstacles=obstacles,
        fine_obstacles=fine_obstacles,
        fine_targets=fine_targets,
        start=start_m,
        config=cfg,
        off_limits=limits,
    )


def without_keep_out(cmap: CostMap, layer_z: float | None = None) -> CostMap:
    """``cmap`` with the avoidance map's core no longer an obstacle (the paper's soft cost
    alone; the planner's fallback when the core leaves no path): only the obstacles are made
    again, the cost is the same. ``layer_z`` [m] as given to :func:`compose_cost_map`."""
    cfg = replace(cmap.config, avoidance_keep_out=0.0)
    obstacles = planning_obstacles(
        cmap.fine_grid, cmap.grid, cmap.fine_obstacles, cmap.fine_targets, cmap.start, None,
        layer_z, downsample=cfg.downsample, margin_cm=cfg.obstacle_margin_cm,
        entity_clear_cm=cfg.entity_clear_radius_cm, target_clear_cm=cfg.target_clear_radius_cm,
        keep_out_fraction=0.0, off_limits=cmap.off_limits)
    obstacles &= ~cmap.target_mask
    return replace(cmap, obstacles=obstacles, config=cfg)


def _fine_targets(aff: NDArray, threshold: float) -> NDArray[np.int64]:
    """Voxels (i, j, k) of the affordance map at or above ``threshold`` × its peak, shape (N, 3).

    Raises:
        EmptyAffordanceError: no voxel is positive.
    """
    peak = float(aff.max())
    if peak <= 0:
        raise EmptyAffordanceError(
            "affordance map has no positive voxel (max value "
            f"{peak:g}); set the target voxels to a value > 0 so something attracts the entity"
        )
    return nonzero_voxels(aff >= peak * threshold).astype(np.int64, copy=False)


def _off_limits(mask: NDArray, grid: VoxelGrid) -> NDArray[np.bool_]:
    """``mask`` as a boolean array of shape ``grid.shape``.

    Raises:
        OutOfWorkspaceError: another shape (names both).
    """
    arr = np.asarray(mask, dtype=bool)
    if arr.shape != grid.shape:
        raise OutOfWorkspaceError(f"off_limits has shape {arr.shape}; expected {grid.shape}")
    return arr


def _non_negative(values: NDArray[np.floating]) -> NDArray[np.floating]:
    """``values`` with negatives raised to 0 (copied only when there are any)."""
    return np.maximum(values, 0) if float(values.min()) < 0 else values


def _avoidance_cost(coarse_shape: tuple[int, ...], pooled: NDArray | None,
                    fine_obstacles: NDArray[np.bool_], cfg: CostMapConfig) -> NDArray[np.float32]:
    """The avoidance term on the planning grid from the non-negative avoidance map pooled onto
    it (None: nothing to avoid): Gaussian-smoothed, normalised (zeros when nothing is to be
    avoided); scene obstacles join it with ``obstacles_as_avoidance``."""
    if cfg.obstacles_as_avoidance and fine_obstacles.any():
        solid = pool_max(fine_obstacles, cfg.downsample).astype(np.float32)
        pooled = solid if pooled is None else np.maximum(pooled, solid)
    if pooled is None or float(pooled.max()) <= 0:
        return np.zeros(coarse_shape, dtype=np.float32)
    return normalise(smooth_zero_padded(pooled.astype(np.float32, copy=False),
                                        cfg.avoidance_sigma / cfg.downsample,
                                        cfg.gaussian_truncate))


def _scene_obstacles(
    grid: VoxelGrid,
    occupancy: NDArray[np.bool_] | None,
    entity_occupancy: NDArray[np.bool_] | None,
    start: NDArray[np.float64],
    fine_targets: NDArray[np.int64],
    cfg: CostMapConfig,
) -> NDArray[np.bool_]:
    """Scene occupancy minus the entity, cleared around the start and the targets."""
    obstacles = np.zeros(grid.shape, dtype=bool)
    if occupancy is None:
        return obstacles
    occ = np.asarray(occupancy)
    if occ.shape != grid.shape:
        raise OutOfWorkspaceError(f"occupancy has shape {occ.shape}; expected {grid.shape}")
    obstacles = occ.astype(bool, copy=True)
    if entity_occupancy is not None:
        ent = np.asarray(entity_occupancy, dtype=bool)
        if ent.shape != grid.shape:
            raise OutOfWorkspaceError(
                f"entity_occupancy has shape {ent.shape}; expected {grid.shape}"
            )
        obstacles &= ~ent
    clear_sphere(obstacles, grid, start, cfg.entity_clear_radius_cm)
    for target in target_representatives(grid, fine_targets):
        clear_sphere(obstacles, grid, target, cfg.target_clear_radius_cm)
    obstacles[fine_targets[:, 0], fine_targets[:, 1], fine_targets[:, 2]] = False
    return obstacles
