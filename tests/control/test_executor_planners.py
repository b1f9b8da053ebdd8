"""The executor's two planners: the hand's path keeps its distance from what it avoids when the
path is straightened; an object's (a push) keeps the plain straightening."""

import itertools
from dataclasses import replace

import numpy as np

from voxposer.control.config import ExecutorConfig
from voxposer.planning import PathPlanner
from voxposer.valuemaps import ValueMapAPI, VoxelGrid


def _closest(positions: np.ndarray, point: np.ndarray) -> float:
    dense = np.concatenate([np.linspace(a, b, 50) for a, b in itertools.pairwise(positions)])
    return float(np.linalg.norm(dense - point, axis=1).min())


def test_the_hands_straightened_path_keeps_the_unstraightened_distance() -> None:
    grid = VoxelGrid((0, 0, 0), (1, 1, 1))
    api = ValueMapAPI(grid)
    block = np.array([0.5, 0.5, 0.1])
    hand = ExecutorConfig().ee_planner
    rng = np.random.default_rng(0)
    nearer = 0
    for _ in range(6):  # crossings past a "7cm around the block" map
        heading = rng.uniform(0, 2 * np.pi)
        along = np.array([np.cos(heading), np.sin(heading), 0.0])
        side = rng.uniform(-0.06, 0.06) * np.array([-along[1], along[0], 0.0])
        start, target = block - 0.3 * along + side, block + 0.3 * along + side
        affordance = api.get_empty_affordance_map()
        affordance[tuple(grid.world_to_voxel(target))] = 1.0
        avoid = api.set_voxel_by_radius(api.get_empty_avoidance_map(),
                                        grid.world_to_voxel(block), 7, 1.0)
        closest = {name: _closest(PathPlanner(grid, cfg).plan(
            affordance, start, avoidance_map=avoid).trajectory.positions, block)
            for name, cfg in (("grid", replace(hand, shortcut=False)),
                              ("plain", replace(hand, shortcut_keeps_distance=False)),
                              ("hand", hand))}
        assert closest["hand"] >= closest["grid"] - 0.005
        nearer += closest["plain"] < closest["grid"] - 0.01
    assert nearer >= 4  # the plain straightening would have cut toward the block
    assert not ExecutorConfig().object_planner.shortcut_keeps_distance  # pushes: plain
