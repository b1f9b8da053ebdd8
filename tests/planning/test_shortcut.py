"""The found path is straightened only where a straight segment is free and costs no more."""

import itertools

import numpy as np

from voxposer.planning import PathPlanner, PlannerConfig
from voxposer.planning.shortcut import shortcut
from voxposer.valuemaps import ValueMapAPI, VoxelGrid

GRID = VoxelGrid((0, 0, 0), (1, 1, 1), (20, 20, 20))


def _centres(voxels: list[tuple[int, int, int]]) -> np.ndarray:
    return GRID.voxel_to_world(np.array(voxels, dtype=float))


def _line_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    u = (b - a) / np.linalg.norm(b - a)
    rel = points - a
    return np.linalg.norm(rel - (rel @ u)[:, None] * u, axis=1)


def test_a_staircase_in_free_space_becomes_one_straight_segment() -> None:
    stairs = [(i, i // 2, 0) for i in range(12)]  # the grid's way to run at ~27°
    out = shortcut(_centres(stairs), GRID, np.zeros(GRID.shape), np.zeros(GRID.shape, bool), 0.1)
    np.testing.assert_array_equal(out, _centres([stairs[0], stairs[-1]]))


def test_no_segment_crosses_an_obstacle_or_a_costlier_band() -> None:
    blocked = np.zeros(GRID.shape, bool)
    blocked[5, 2:8, :] = True  # a wall the path goes round at y = 8
    path = [(2, 2, 0), (3, 3, 0), (4, 4, 0), (4, 5, 0), (4, 6, 0), (4, 7, 0), (4, 8, 0),
            (5, 8, 0), (6, 8, 0), (6, 7, 0), (6, 6, 0), (6, 5, 0), (6, 4, 0), (7, 3, 0), (8, 2, 0)]
    out = shortcut(_centres(path), GRID, np.zeros(GRID.shape), blocked, 0.1)
    assert len(out) < len(path)
    dense = np.concatenate([np.linspace(a, b, 500) for a, b in itertools.pairwise(out)])
    idx = GRID.world_to_voxel(dense, clip=True)
    assert not blocked[idx[:, 0], idx[:, 1], idx[:, 2]].any()
    # the same detour around a costly (not blocked) band stays: a straight cut costs more
    cost = np.zeros(GRID.shape)
    cost[5, 2:8, :] = 50.0
    out = shortcut(_centres(path), GRID, cost, np.zeros(GRID.shape, bool), 0.1)
    assert max(GRID.world_to_voxel(out)[:, 1]) == 8


def test_a_climbing_plan_keeps_to_the_straight_way() -> None:
    """A target 25 cm higher than the start: the grid's optimal path climbs on diagonals and
    turns away from the heading (the artefact of the dev record), the shortened one does not."""
    grid = VoxelGrid((0, 0, 0), (1, 1, 1))
    api = ValueMapAPI(grid)
    start, target = np.array([0.2, 0.2, 0.05]), np.array([0.35, 0.65, 0.30])
    affordance = api.get_empty_affordance_map()
    affordance[tuple(grid.world_to_voxel(target))] = 1.0
    off = {}
    for straighten in (False, True):
        plan = PathPlanner(grid, PlannerConfig(shortcut=straighten)).plan(affordance, start)
        off[straighten] = float(_line_distance(plan.trajectory.positions, start, target).max())
        assert np.linalg.norm(plan.target - grid.voxel_to_world(grid.world_to_voxel(target))) < 1e-9
    assert off[False] > 0.03
    assert off[True] < 0.015


def test_given_the_avoidance_a_segment_comes_no_nearer_the_avoided_object() -> None:
    """A faint avoidance cost: cutting straight through it costs less than the detour, so the
    plain shortening takes the cut; told the avoidance term, it keeps the detour's distance."""
    path = [(2, 2, 0), (3, 3, 0), (4, 4, 0), (4, 5, 0), (4, 6, 0), (4, 7, 0), (4, 8, 0),
            (5, 8, 0), (6, 8, 0), (6, 7, 0), (6, 6, 0), (6, 5, 0), (6, 4, 0), (7, 3, 0), (8, 2, 0)]
    avoid = np.zeros(GRID.shape)
    avoid[5, 2:8, :] = 1.0  # what the detour keeps away from
    cost = 0.01 * avoid
    free = np.zeros(GRID.shape, bool)
    cut = shortcut(_centres(path), GRID, cost, free, 0.1)
    kept = shortcut(_centres(path), GRID, cost, free, 0.1, avoid)
    assert max(GRID.world_to_voxel(cut)[:, 1]) < 8  # straight through the faint cost
    dense = np.concatenate([np.linspace(a, b, 500) for a, b in itertools.pairwise(kept)])
    idx = GRID.world_to_voxel(dense, clip=True)
    assert avoid[idx[:, 0], idx[:, 1], idx[:, 2]].max() == 0.0  # never entered
    assert len(kept) < len(path)  # yet straightened where it could
