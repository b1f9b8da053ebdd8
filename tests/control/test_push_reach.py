"""A pushed object's path keeps within the arm's pushing reach (``push_reach_m``)."""

from types import SimpleNamespace

import numpy as np
import pytest

from voxposer import tabletop
from voxposer.control.config import ExecutorConfig
from voxposer.control.pushing_loop import _plan_object
from voxposer.control.table_layer import beyond_push_reach
from voxposer.errors import ConfigError
from voxposer.planning import PathPlanner
from voxposer.valuemaps import VoxelGrid

BASE = np.array(tabletop.ROBOT_BASE)
GRID = VoxelGrid(tabletop.WORKSPACE_MIN, tabletop.WORKSPACE_MAX, tabletop.GRID_SHAPE)
HEIGHT = 0.025


def _reach(points: np.ndarray) -> np.ndarray:
    return np.linalg.norm(points[:, :2] - BASE[:2], axis=1)


def _loop(reach_m: tuple[float, float]) -> SimpleNamespace:
    """What ``_plan_object`` uses of the closed loop: the scene is free, the object planner is
    the executor's own."""
    config = ExecutorConfig(push_reach_m=reach_m)
    perceiver = SimpleNamespace(
        grid=GRID, scene_occupancy=lambda *a, **k: np.zeros(GRID.shape, dtype=bool))
    return SimpleNamespace(config=config, perceiver=perceiver,
                           robot=SimpleNamespace(base_position=BASE),
                           object_planner=PathPlanner(GRID, config.object_planner))


def _around(reach_m: tuple[float, float], start: tuple[float, float],
            target: tuple[float, float], obstacle: tuple[float, float]):
    """The object planner's path of a block from ``start`` to ``target`` (x, y [m]) around a
    10 cm avoidance sphere at ``obstacle``."""
    affordance = np.zeros(GRID.shape, dtype=np.float32)
    affordance[tuple(GRID.world_to_voxel([*target, HEIGHT]))] = 1.0
    avoid = np.zeros(GRID.shape, dtype=np.float32)
    centres = GRID.voxel_to_world(np.argwhere(np.ones(GRID.shape, dtype=bool)))
    inside = np.linalg.norm(centres - [*obstacle, HEIGHT], axis=1) <= 0.10
    avoid.reshape(-1)[inside] = 1.0
    entity = {"position": np.array([*start, HEIGHT]), "occupancy": None}
    values = {"affordance_map": affordance, "avoidance_map": avoid}
    return _plan_object(_loop(reach_m), "block", entity, values, sliding=False)


# a block 0.59 m out pushed across the table round a sphere 3 cm behind its way: round the
# sphere's front is shorter, and takes the block 0.65 m or more from the base
FAR = {"start": (-0.05, 0.2), "target": (-0.05, -0.2), "obstacle": (-0.08, 0.0)}
# a block 0.35 m out pushed across round a sphere 3 cm in front of its way: round its back is
# shorter, and passes within 0.2 m of the base
NEAR = {"start": (-0.35, 0.25), "target": (-0.35, -0.25), "obstacle": (-0.32, 0.0)}


def test_the_path_goes_round_the_near_side_when_the_far_one_is_out_of_reach() -> None:
    free = _around((0.0, 0.0), **FAR).trajectory.positions
    assert _reach(free).max() > 0.66, "without the limit the shorter front detour is taken"
    kept = _around((0.0, 0.62), **FAR)
    assert kept.reached
    assert _reach(kept.trajectory.positions).max() <= 0.62 + 0.015  # a planning voxel
    assert kept.trajectory.positions[:, 0].min() < -0.17, "round the back of the sphere"


def test_the_path_keeps_off_the_arm_s_column() -> None:
    free = _around((0.0, 0.0), **NEAR).trajectory.positions
    assert _reach(free).min() < 0.2, "without the limit the shorter back detour is taken"
    kept = _around((0.32, 0.72), **NEAR)
    assert kept.reached
    assert _reach(kept.trajectory.positions).min() >= 0.32 - 0.015
    assert kept.trajectory.positions[:, 0].max() > -0.23, "round the front of the sphere"


def test_a_target_beyond_the_reach_is_still_planned_to() -> None:
    """The limit gives way where it leaves no path: the target itself lies 0.72 m out."""
    plan = _around((0.0, 0.55), FAR["start"], (0.08, -0.2), FAR["obstacle"])
    assert plan.reached
    np.testing.assert_allclose(plan.target[:2], [0.08, -0.2], atol=0.011)


def test_beyond_push_reach_marks_the_table_outside_the_band_in_every_layer() -> None:
    out = beyond_push_reach(GRID, BASE, (0.3, 0.7))
    assert out.shape == GRID.shape
    for point, off in (([0.2, 0.0, 0.02], True), ([0.05, 0.0, 0.5], False),
                       ([-0.2, 0.45, 0.02], False), ([0.0, 0.45, 0.3], True),
                       ([-0.45, 0.1, 0.02], True), ([-0.25, 0.0, 0.02], False)):
        assert out[tuple(GRID.world_to_voxel(point))] == off, point


@pytest.mark.parametrize("value", [(-0.1, 0.7), (0.5, 0.3), (0.3, 7.0), (0.3,), 0.7, "far"])
def test_a_bad_push_reach_names_the_field(value: object) -> None:
    with pytest.raises(ConfigError, match="push_reach_m"):
        ExecutorConfig(push_reach_m=value)  # type: ignore[arg-type]


def test_the_reach_gives_way_before_the_avoidance_core_does() -> None:
    """Within a 0.40-0.56 m band the only way round the sphere (0.38-0.58 m out) cuts through
    its core: the path leaves the band rather than cut into what it must avoid."""
    squeeze = {"start": (-0.12, 0.25), "target": (-0.12, -0.25), "obstacle": (-0.12, 0.0)}
    kept = _around((0.40, 0.56), **squeeze)
    assert kept.reached and not kept.relaxed
    centre = np.array([*squeeze["obstacle"], HEIGHT])
    gap = np.linalg.norm(kept.trajectory.positions - centre, axis=1).min()
    assert gap >= 0.10 - 0.02, "kept out of the sphere"
    reach = _reach(kept.trajectory.positions)
    assert reach.min() < 0.38 or reach.max() > 0.58, "by leaving the band"
