"""Affordances relative to the moving entity are anchored; others keep following the scene."""

import numpy as np

from tests.perceive import perceive
from voxposer.control import ClosedLoopController
from voxposer.control.anchoring import SelfRelativeAnchor
from voxposer.envs import TabletopWorld
from voxposer.valuemaps import ValueMapAPI, VoxelGrid

GRID = VoxelGrid((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (100, 100, 100))


def _point_map(point: np.ndarray) -> np.ndarray:
    m = np.zeros(GRID.shape, dtype=np.float32)
    m[tuple(GRID.world_to_voxel(point))] = 1
    return m


def test_a_target_that_moves_with_the_entity_is_anchored_at_its_first_value() -> None:
    entity = np.array([0.5, 0.5, 0.2])
    anchor = SelfRelativeAnchor(lambda: _point_map(entity + [0, 0, 0.05]), lambda: entity, GRID)
    first = np.argwhere(anchor())[0]
    for _ in range(5):
        entity = entity + [0, 0, 0.02]  # the entity climbs toward the target...
        current = np.argwhere(anchor())[0]
    assert anchor.anchored
    assert np.array_equal(current, first)  # ...and the target stays where it was first


def test_fixed_and_independently_moving_targets_are_never_anchored() -> None:
    entity = np.array([0.2, 0.2, 0.2])
    target = np.array([0.6, 0.6, 0.3])
    anchor = SelfRelativeAnchor(lambda: _point_map(target), lambda: entity, GRID)
    anchor()
    for _ in range(5):
        entity = entity + [0.03, 0.0, 0.0]
        anchor()
    assert not anchor.anchored
    target = target + [0.1, 0.0, 0.0]  # the object it refers to is displaced: follow it
    assert np.argwhere(anchor())[0][0] == GRID.world_to_voxel(target)[0]
    assert not anchor.anchored


def test_the_hand_reaches_a_point_above_itself_instead_of_chasing_it(
    world: TabletopWorld,
) -> None:
    world.reset(np.random.default_rng(6))
    api = ValueMapAPI(world.grid, lambda: world.get_ee_pose()[1], world.get_gripper_state)
    start = world.get_ee_pose()[0]

    def above_the_gripper() -> np.ndarray:  # re-evaluated every step, like a cached program
        m = api.get_empty_affordance_map()
        m[tuple(world.grid.world_to_voxel(world.get_ee_pose()[0] + [0, 0, 0.08]))] = 1
        return m

    result = ClosedLoopController(world, perceive(world), np.random.default_rng(6))(
        lambda: perceive(world).detect("gripper"), above_the_gripper
    )
    assert result.success, result.message
    assert abs(world.get_ee_pose()[0][2] - (start[2] + 0.08)) < 0.03


def test_a_drawer_pushed_by_a_handle_relative_target_closes_all_the_way(
    world: TabletopWorld,
) -> None:
    from voxposer.envs.layout import SceneLayout

    world.reset(np.random.default_rng(7),
                SceneLayout(blocks=("blue",), drawer_openings={"top": 0.15}, extra_blocks=(0, 0)))
    api = ValueMapAPI(world.grid, lambda: world.get_ee_pose()[1], world.get_gripper_state)
    axis = world.drawer_axis("top drawer")

    def twelve_cm_in() -> np.ndarray:  # less than the opening: only "until it stops" closes it
        m = api.get_empty_affordance_map()
        handle = perceive(world).detect("top drawer handle").position
        m[tuple(world.grid.world_to_voxel(handle - 0.12 * axis))] = 1
        return m

    result = ClosedLoopController(world, perceive(world), np.random.default_rng(7))(
        lambda: perceive(world).detect("top drawer handle"), twelve_cm_in
    )
    assert result.success, result.message
    assert world.drawer_opening("top") < 0.02
