"""The avoidance map's core is kept out of (with a fallback to the soft cost), and a path can be
held in one layer (an object sliding on the table)."""

import numpy as np
import pytest

from voxposer.control.table_layer import onto_layer
from voxposer.planning import PathPlanner, PlannerConfig
from voxposer.valuemaps import CostMapConfig, VoxelGrid

GRID = VoxelGrid((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (50, 50, 50))
START, GOAL, KEEP = np.array([0.1, 0.5, 0.3]), np.array([0.9, 0.5, 0.3]), np.array([0.5, 0.52, 0.3])


def _maps(radius_m: float = 0.15, around: np.ndarray = KEEP) -> tuple[np.ndarray, np.ndarray]:
    aff = np.zeros(GRID.shape, np.float32)
    aff[tuple(GRID.world_to_voxel(GOAL))] = 1
    centres = GRID.voxel_to_world(np.argwhere(np.ones(GRID.shape, bool)))
    avoid = (np.linalg.norm(centres - around, axis=1) <= radius_m).reshape(GRID.shape)
    return aff, avoid.astype(np.float32)


def _closest(plan, point: np.ndarray) -> float:
    return float(np.linalg.norm(plan.trajectory.positions - point, axis=1).min())


@pytest.mark.parametrize("keep_out", [0.0, 0.5])
def test_the_core_of_what_to_avoid_is_kept_out_of(keep_out: float) -> None:
    aff, avoid = _maps()
    cfg = PlannerConfig(cost=CostMapConfig(avoidance_keep_out=keep_out))
    plan = PathPlanner(GRID, cfg).plan(aff, START, avoidance_map=avoid)
    assert plan.reached
    if keep_out:
        assert _closest(plan, KEEP) >= 0.15 - 0.03  # outside the 15 cm sphere (voxel rounding)
    else:  # the paper's soft cost alone lets the path cut into it
        assert _closest(plan, KEEP) < 0.12


def test_a_start_inside_the_core_can_still_leave_it() -> None:
    aff, avoid = _maps()
    inside = KEEP + [-0.05, 0.0, 0.0]
    plan = PathPlanner(GRID).plan(aff, inside, avoidance_map=avoid)
    assert plan.reached and np.linalg.norm(plan.trajectory.positions[-1] - GOAL) < 0.03


def test_a_start_at_the_edge_of_a_flat_core_goes_round_it_no_deeper() -> None:
    # a flat 15 cm sphere ("15cm around …" set to one value), the start 13 cm from its
    # centre on the straight line to the goal: the path leaves round it, never nearer
    aff, avoid = _maps()
    edge = KEEP + [-0.13, -0.02, 0.0]
    plan = PathPlanner(GRID).plan(aff, edge, avoidance_map=avoid)
    start_gap = float(np.linalg.norm(edge - KEEP))
    assert plan.reached
    assert _closest(plan, KEEP) >= start_gap - 0.03  # not deeper than it started (voxels)
    soft = PathPlanner(GRID, PlannerConfig(cost=CostMapConfig(avoidance_keep_out=0.0)))
    assert _closest(soft.plan(aff, edge, avoidance_map=avoid), KEEP) < start_gap - 0.03


def test_a_target_inside_the_core_falls_back_to_the_soft_cost() -> None:
    aff, avoid = _maps(radius_m=0.2, around=GOAL)  # asked to go where it must stay away from
    plan = PathPlanner(GRID).plan(aff, START, avoidance_map=avoid)
    assert plan.reached and plan.cost_map.config.avoidance_keep_out == 0.0
    assert plan.relaxed
    kept = PathPlanner(GRID).plan(*_maps()[:1], START, avoidance_map=_maps()[1])
    assert not kept.relaxed


def test_a_sliding_object_stays_in_its_layer() -> None:
    aff, avoid = _maps()
    low = START.copy()
    low[2] = 0.05
    flat = onto_layer(GRID, aff, float(low[2]))
    assert flat[:, :, GRID.world_to_voxel(low)[2]].max() == 1 and flat.sum() == 1
    free = PathPlanner(GRID).plan(flat, low, avoidance_map=avoid)
    held = PathPlanner(GRID).plan(flat, low, avoidance_map=avoid, layer_z=float(low[2]))
    assert held.reached
    assert np.ptp(held.trajectory.positions[:, 2]) < GRID.resolution[2] * 2 + 1e-9
    assert np.ptp(free.trajectory.positions[:, 2]) > np.ptp(held.trajectory.positions[:, 2])
