"""The benchmark's planner scenes: the path takes the one way through, or none is reported."""

import numpy as np
import pytest

from voxposer.errors import ConfigError, TargetUnreachableError
from voxposer.planning import PathPlanner
from voxposer.planning.obstacle_scenes import BOX_HALF_M, make_scene


def _plan(scene):
    return PathPlanner(scene.grid).plan(scene.affordance_map, scene.start,
                                        avoidance_map=scene.avoidance_map,
                                        occupancy=scene.occupancy)


@pytest.mark.parametrize("seed", [0, 1])
def test_a_wall_is_crossed_through_its_gap(seed: int) -> None:
    scene = make_scene("wall", np.random.default_rng(seed))
    plan = _plan(scene)
    assert plan.reached
    pos = plan.trajectory.positions
    crossing = pos[(pos[:, 0] > 0.55) & (pos[:, 0] < 0.58)]
    assert len(crossing)
    # where it crosses, the wall has no points: the path went through the gap
    wall = scene.points[(scene.points[:, 0] >= 0.55) & (scene.points[:, 0] <= 0.58)]
    gaps = np.linalg.norm(wall[None, :, 1:] - crossing[:, None, 1:], axis=2).min(axis=1)
    assert gaps.min() > 0.01


@pytest.mark.parametrize("seed", [0, 3])
def test_an_enclosed_target_is_entered_through_the_open_face(seed: int) -> None:
    scene = make_scene("enclosed", np.random.default_rng(seed))
    plan = _plan(scene)
    assert plan.reached
    assert np.linalg.norm(plan.target - scene.target) < 0.01
    inside = np.all(np.abs(plan.trajectory.positions - scene.target) < BOX_HALF_M - 0.02, axis=1)
    first = int(np.argmax(inside))
    assert inside[first:].all()  # once inside it stays inside: it did not pass a wall


def test_a_sealed_target_is_reported_unreachable() -> None:
    scene = make_scene("sealed", np.random.default_rng(0))
    with pytest.raises(TargetUnreachableError, match=r"closest reachable point .* cm from"):
        _plan(scene)


def test_an_unknown_scene_kind_names_the_kinds() -> None:
    with pytest.raises(ConfigError, match="cup, wall, enclosed, sealed"):
        make_scene("maze", np.random.default_rng(0))
