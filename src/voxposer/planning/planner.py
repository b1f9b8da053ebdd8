"""The motion planner: value maps → cost map → global path → smoothed 6-DoF trajectory.

Paper Sec. 4 "Motion Planner": only the affordance and avoidance maps enter the optimisation;
the rotation, velocity and gripper maps are then read along the path. Unlike the paper's
release (greedy descent, kept here as ``method="greedy"`` for comparison) the path is the
global lowest-cost one, so an obstacle near the target cannot trap the planner. A path that ends
closing the gripper (a grasp) ends with a straight approach along the hand's approach axis.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from voxposer.errors import ConfigError, StartBlockedError, TargetUnreachableError
from voxposer.geometry.frames import TOP_DOWN_QUAT
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.planning.planner_config import PlanMethod, PlannerConfig
from voxposer.planning.search import astar, greedy_descent
from voxposer.planning.shortcut import shortcut
from voxposer.planning.trajectory import Trajectory, collides, extract_trajectory, resample, smooth
from voxposer.valuemaps.cost import CostMap, CostMapConfig, compose_cost_map, without_keep_out
from voxposer.valuemaps.maps import check_value_map


@dataclass(frozen=True)
class Plan:
    """A planned trajectory with what produced it.

    Attributes:
        trajectory: the 6-DoF trajectory (ends on the target when ``reached``).
        cost_map: the cost map the search ran on.
        voxel_path: voxels visited by the search on ``cost_map.grid``, shape (M, 3).
        reached: whether the path ends on an affordance target.
        path_cost: objective value of ``voxel_path`` (see :mod:`voxposer.planning.search`).
        method: ``"global"`` or ``"greedy"``.
        timings_ms: wall time per stage [ms]: postprocess, search, trajectory, total.
        relaxed: the avoidance map's core left no path, so the path kept to its soft cost
            only (:func:`~voxposer.valuemaps.cost.without_keep_out`).
    """

    trajectory: Trajectory
    cost_map: CostMap
    voxel_path: NDArray[np.int64]
    reached: bool
    path_cost: float
    method: PlanMethod
    timings_ms: dict[str, float]
    relaxed: bool = False

    @property
    def target(self) -> NDArray[np.float64]:
        """The final waypoint [m], shape (3,)."""
        return self.trajectory.positions[-1]


class PathPlanner:
    """Plans 6-DoF trajectories over value maps on one workspace grid."""

    def __init__(self, grid: VoxelGrid, config: PlannerConfig | None = None) -> None:
        self.grid = grid
        self.config = config or PlannerConfig()

    def plan(
        self,
        affordance_map: NDArray,
        start: ArrayLike,
        *,
        avoidance_map: NDArray | None = None,
        rotation_map: NDArray | None = None,
        velocity_map: NDArray | None = None,
        gripper_map: NDArray | None = None,
        occupancy: NDArray[np.bool_] | None = None,
        entity_occupancy: NDArray[np.bool_] | None = None,
        current_quat: ArrayLike = TOP_DOWN_QUAT,
        current_gripper: float = 0.0,
        layer_z: float | None = None,
        off_limits: NDArray[np.bool_] | None = None,
    ) -> Plan:
        """Plan from ``start`` [m] to the affordance target.

        Args:
            affordance_map, avoidance_map, rotation_map, velocity_map, gripper_map: value maps
                on ``self.grid`` (see :mod:`voxposer.valuemaps.maps`); None = not specified.
            start: the entity's position [m], shape (3,).
            occupancy: scene obstacle voxels, shape ``grid.shape``.
            entity_occupancy: the moving entity's own voxels (not obstacles).
            current_quat: orientation (x, y, z, w) used where no rotation map is given.
            current_gripper: gripper state used where no gripper map is given.
            layer_z: keep the path in the planning layer at this height [m] (an object that
                slides on the table); None: anywhere in the workspace.
            off_limits: voxels the path may not enter although nothing is there, shape
                ``grid.shape`` (see :func:`~voxposer.valuemaps.cost.compose_cost_map`).

        Raises:
            InvalidMapError, EmptyAffordanceError, OutOfWorkspaceError: bad maps or start.
            StartBlockedError: the start is enclosed by obstacles (global method).
            TargetUnreachableError: no free path reaches a target (global method).
        """
        cfg = self.config
        t0 = time.perf_counter()
        cost_cfg = cfg.cost
        if cfg.method == "greedy":  # the release: full resolution, plain Gaussian, soft obstacles
            cost_cfg = replace(
                cost_cfg, downsample=1, gaussian_truncate=4.0, obstacles_as_avoidance=True
            )
        cmap, search, t1 = self._compose_and_search(
            affordance_map, start, avoidance_map, occupancy, entity_occupancy, cost_cfg, layer_z,
            off_limits)
        plan = self._finish(cmap, search, (t0, t1), rotation_map, velocity_map, gripper_map,
                            current_quat, current_gripper)
        if cmap.config.avoidance_keep_out < cost_cfg.avoidance_keep_out:
            plan = replace(plan, relaxed=True)
        return plan

    def plan_on_cost(
        self,
        cost_map: CostMap,
        *,
        rotation_map: NDArray | None = None,
        velocity_map: NDArray | None = None,
        gripper_map: NDArray | None = None,
        current_quat: ArrayLike = TOP_DOWN_QUAT,
        current_gripper: float = 0.0,
    ) -> Plan:
        """Plan on a cost map made elsewhere (a learned one: the U-Net + MP baseline) instead of
        one composed from value maps; the search starts at ``cost_map.start`` [m], shape (3,)
        (its obstacles were cleared around it), and the trajectory is made as by :meth:`plan`.

        Args:
            cost_map: on ``self.grid`` coarsened (``cost_map.fine_grid`` must be ``self.grid``).
            rotation_map, velocity_map, gripper_map, current_quat, current_gripper: as
                :meth:`plan`.

        Raises:
            ConfigError: ``cost_map`` was made on another workspace grid (names both shapes).
            StartBlockedError, TargetUnreachableError: as :meth:`plan` (global method).
        """
        if cost_map.fine_grid != self.grid:
            raise ConfigError(f"the cost map was made on a workspace grid of shape "
                              f"{cost_map.fine_grid.shape}, but this planner plans on "
                              f"{self.grid.shape}")
        t0 = time.perf_counter()
        return self._finish(cost_map, self._find_path(cost_map), (t0, t0), rotation_map,
                            velocity_map, gripper_map, current_quat, current_gripper)

    def _finish(
        self, cmap: CostMap, search: tuple[NDArray[np.int64], float, bool],
        clock: tuple[float, float], rotation_map: NDArray | None, velocity_map: NDArray | None,
        gripper_map: NDArray | None, current_quat: ArrayLike, current_gripper: float,
    ) -> Plan:
        """The plan of a searched ``cmap``: waypoints, the maps read along them, and a straight
        final approach when the path ends closing the gripper; ``clock`` holds the start and
        the end of cost-map composition (``time.perf_counter`` [s])."""
        cfg = self.config
        path, path_cost, reached = search
        t0, t1 = clock
        t2 = time.perf_counter()
        points = self._waypoints(cmap, path, reached)

        # validated once here (shape, dtype, NaN/inf), then sampled for each candidate path
        rotation_map, velocity_map, gripper_map = (
            None if m is None else check_value_map(kind, m, self.grid) for kind, m in
            (("rotation", rotation_map), ("velocity", velocity_map), ("gripper", gripper_map)))

        def read_maps(positions: NDArray[np.float64]) -> Trajectory:
            return extract_trajectory(
                positions, self.grid, rotation_map=rotation_map, velocity_map=velocity_map,
                gripper_map=gripper_map, checked=True,
                default_quat=np.asarray(current_quat, dtype=np.float64),
                default_gripper=current_gripper)

        traj = read_maps(points)
        grasping = reached and current_gripper < 0.5 and traj.gripper[-1] >= 0.5
        if grasping and cfg.grasp_approach_m > 0:  # approach what the gripper closes on
            approach = self._descend_onto(points, traj.quaternions[-1])
            if not collides(approach, self.grid, cmap.fine_obstacles):
                traj = read_maps(approach)
        t3 = time.perf_counter()
        timings = {"postprocess": (t1 - t0) * 1e3, "search": (t2 - t1) * 1e3,
                   "trajectory": (t3 - t2) * 1e3, "total": (t3 - t0) * 1e3}
        return Plan(traj, cmap, path, reached, path_cost, cfg.method, timings)

    def _compose_and_search(
        self, affordance_map: NDArray, start: ArrayLike, avoidance_map: NDArray | None,
        occupancy: NDArray[np.bool_] | None, entity_occupancy: NDArray[np.bool_] | None,
        cost_cfg: CostMapConfig, layer_z: float | None, off_limits: NDArray[np.bool_] | None,
    ) -> tuple[CostMap, tuple[NDArray[np.int64], float, bool], float]:
        """(cost map, its path search, the time the first map was composed): with the avoidance
        map's core kept out, or — when that leaves no path — with the soft avoidance cost only."""
        cmap = compose_cost_map(
            self.grid, affordance_map, start, avoidance_map, occupancy, entity_occupancy, cost_cfg,
            layer_z=layer_z, off_limits=off_limits)
        t1 = time.perf_counter()
        try:
            return cmap, self._find_path(cmap), t1
        except (StartBlockedError, TargetUnreachableError):
            if avoidance_map is None or cost_cfg.avoidance_keep_out <= 0:
                raise
        cmap = without_keep_out(cmap, layer_z)
        return cmap, self._find_path(cmap), t1

    def _find_path(self, cmap: CostMap) -> tuple[NDArray[np.int64], float, bool]:
        """(voxel path, its cost, whether it reaches a target) by the configured method: the
        release's greedy descent (which may stop short), or the global search (which reaches a
        target or raises)."""
        cfg = self.config
        start_vox = cmap.grid.world_to_voxel(cmap.start, clip=True)
        if cfg.method != "greedy":
            path, path_cost = self._search(cmap, start_vox)
            return path, path_cost, True
        path = greedy_descent(
            cmap.cost,
            np.zeros_like(cmap.obstacles),
            start_vox,
            radius=cfg.greedy_radius,
            max_steps=cfg.greedy_max_steps,
        )
        reached = bool(cmap.target_mask[tuple(path[-1])])
        return path, float(np.sum(cmap.cost[path[1:, 0], path[1:, 1], path[1:, 2]])), reached

    def _search(
        self, cmap: CostMap, start_vox: NDArray[np.int64]
    ) -> tuple[NDArray[np.int64], float]:
        cfg = self.config
        d_max = float(cmap.target_distance.max())
        scale = cfg.cost.affordance_weight / d_max if d_max > 0 else 0.0
        result = astar(
            cmap.cost,
            cmap.obstacles,
            cmap.target_mask,
            cmap.target_distance,
            start_vox,
            length_weight=cfg.length_weight,
            affordance_scale=scale,
        )
        if len(result.path):
            return result.path, result.cost
        start_m = np.round(cmap.start, 3).tolist()
        if result.expanded <= 1:
            raise StartBlockedError(
                f"start {start_m} m (voxel {start_vox.tolist()}) is enclosed by obstacles on every "
                f"side; clear space around the entity (entity_clear_radius_cm="
                f"{cfg.cost.entity_clear_radius_cm}) or move it"
            )
        closest = np.round(cmap.grid.voxel_to_world(result.closest), 3).tolist()
        gap = float(cmap.target_distance[tuple(result.closest)] * cmap.grid.resolution.min())
        raise TargetUnreachableError(
            f"no collision-free path from {start_m} m to the affordance target: obstacles enclose it; "
            f"the closest reachable point is {closest} m, {gap * 100:.1f} cm from the target "
            f"({result.expanded} voxels searched)"
        )

    def _waypoints(
        self, cmap: CostMap, path: NDArray[np.int64], reached: bool
    ) -> NDArray[np.float64]:
        """Polyline through the path voxels, from the exact start to the exact target [m]."""
        cfg = self.config
        centres = cmap.grid.voxel_to_world(path)
        end = self._target_point(cmap, path[-1]) if reached else centres[-1]
        raw = np.vstack([cmap.start, centres[1:-1], end]) if len(path) > 1 else \
            np.vstack([cmap.start, end])
        if cfg.shortcut and cfg.method == "global":
            straight = shortcut(raw, cmap.grid, cmap.cost, cmap.obstacles, cfg.length_weight,
                                cmap.avoidance_cost if cfg.shortcut_keeps_distance else None)
            if not collides(straight, self.grid, cmap.fine_obstacles):
                raw = straight
        raw = resample(raw, cfg.waypoint_spacing_m)
        smoothed = resample(
            smooth(raw, cfg.savgol_window, cfg.savgol_polyorder), cfg.waypoint_spacing_m
        )
        if not collides(smoothed, self.grid, cmap.fine_obstacles):
            return smoothed
        return raw

    def _descend_onto(
        self, points: NDArray[np.float64], quat: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """``points`` (shape (N, 3), [m]) ending with a straight approach onto the last one
        along the hand's approach axis (local +z of orientation ``quat``, (x, y, z, w)).

        Points inside the approach cylinder (within ``grasp_approach_radius_m`` of the approach
        line, less than ``grasp_approach_m`` before the target along it) are dropped from the
        first one that enters it; the path then goes to the point ``grasp_approach_m`` before the
        target and straight on to it. Once the start is on the approach line (within 1 cm) the
        path is the straight line to the target.
        """
        cfg = self.config
        end = points[-1]
        axis = Rotation.from_quat(quat).apply([0.0, 0.0, 1.0])
        rel = points - end
        before = -(rel @ axis)  # distance before the target along the approach [m]
        radial = np.linalg.norm(rel + before[:, None] * axis, axis=1)
        if radial[0] <= 0.01 and before[0] >= 0.0:
            return resample(np.vstack([points[0], end]), cfg.waypoint_spacing_m)
        inside = (radial < cfg.grasp_approach_radius_m) & (before < cfg.grasp_approach_m)
        first = int(np.argmax(inside)) if inside.any() else len(points) - 1
        head = points[: max(first, 1)]
        pre = end - cfg.grasp_approach_m * axis
        return resample(np.vstack([head, pre, end]), cfg.waypoint_spacing_m)

    def _target_point(self, cmap: CostMap, coarse_voxel: NDArray[np.int64]) -> NDArray[np.float64]:
        """The fine target voxel inside the reached coarse voxel nearest its centre [m]."""
        f = cmap.config.downsample
        inside = np.all(cmap.fine_targets // f == coarse_voxel, axis=1)
        candidates = self.grid.voxel_to_world(cmap.fine_targets[inside])
        centre = cmap.grid.voxel_to_world(coarse_voxel)
        return candidates[int(np.argmin(np.linalg.norm(candidates - centre, axis=1)))]
