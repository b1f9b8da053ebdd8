"""``PathPlanner.plan_on_cost``: the planner's search and trajectory on a cost map made
elsewhere (the U-Net + MP baseline's learned one) — it ends at the map's minimum, avoids its
obstacles, and on a composed map gives what ``plan`` gives."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from voxposer.errors import ConfigError
from voxposer.planning import PathPlanner
from voxposer.planning.synthetic_scene import SyntheticScene, make_synthetic_scene
from voxposer.valuemaps import VoxelGrid
from voxposer.valuemaps.cost import CostMap, compose_cost_map


@pytest.fixture(scope="module")
def scene() -> SyntheticScene:
    return make_synthetic_scene(np.random.default_rng(0))


def _dense_voxels(grid: VoxelGrid, positions: np.ndarray) -> np.ndarray:
    """Fine voxels along a polyline [m], shape (N, 3), sampled 8 times per segment."""
    seg = np.linspace(0, 1, 9)[:, None, None]
    pts = (positions[:-1][None] * (1 - seg) + positions[1:][None] * seg).reshape(-1, 3)
    return grid.world_to_voxel(pts)


def _learned_like(scene: SyntheticScene) -> CostMap:
    """The scene's cost map with its cost replaced by a field a model could predict: 3 × the
    normalised straight-line distance to the target, blind to the obstacles."""
    cmap = compose_cost_map(scene.grid, scene.affordance_map, scene.start,
                            occupancy=scene.occupancy)
    centres = cmap.grid.voxel_to_world(np.argwhere(np.ones(cmap.grid.shape, dtype=bool)))
    dist = np.linalg.norm(centres - scene.target, axis=1).reshape(cmap.grid.shape)
    return replace(cmap, cost=(3.0 * dist / dist.max()).astype(np.float32))


def test_the_path_ends_at_the_cost_minimum_and_avoids_the_obstacles(scene) -> None:
    cmap = _learned_like(scene)
    plan = PathPlanner(scene.grid).plan_on_cost(cmap, gripper_map=scene.gripper_map)
    assert plan.reached and plan.cost_map is cmap
    end = tuple(plan.voxel_path[-1])
    assert cmap.target_mask[end]
    assert cmap.cost[end] <= float(cmap.cost.min()) + 0.05
    np.testing.assert_allclose(plan.trajectory.positions[0], scene.start)
    assert np.linalg.norm(plan.target - scene.target) < 0.02
    vox = _dense_voxels(scene.grid, plan.trajectory.positions)
    assert not cmap.fine_obstacles[vox[:, 0], vox[:, 1], vox[:, 2]].any()
    assert not cmap.obstacles[tuple(plan.voxel_path.T)].any()
    # the straight line runs through the cup: the obstacle-blind cost alone would not avoid it
    straight = _dense_voxels(scene.grid, np.stack([scene.start, scene.target]))
    assert cmap.fine_obstacles[straight[:, 0], straight[:, 1], straight[:, 2]].any()
    assert plan.trajectory.gripper[-1] == 1.0  # the maps are read along the path


def test_on_the_composed_map_it_plans_what_plan_plans(scene) -> None:
    planner = PathPlanner(scene.grid)
    full = planner.plan(scene.affordance_map, scene.start, avoidance_map=scene.avoidance_map,
                        occupancy=scene.occupancy, rotation_map=scene.rotation_map)
    again = planner.plan_on_cost(full.cost_map, rotation_map=scene.rotation_map)
    np.testing.assert_array_equal(again.voxel_path, full.voxel_path)
    np.testing.assert_allclose(again.trajectory.positions, full.trajectory.positions)
    np.testing.assert_allclose(again.trajectory.quaternions, full.trajectory.quaternions)
    assert again.path_cost == pytest.approx(full.path_cost)


def test_a_cost_map_of_another_workspace_grid_is_refused(scene) -> None:
    other = VoxelGrid([0, 0, 0], [1, 1, 1], (50, 50, 50))
    with pytest.raises(ConfigError, match=r"shape \(100, 100, 100\).*\(50, 50, 50\)"):
        PathPlanner(other).plan_on_cost(_learned_like(scene))
