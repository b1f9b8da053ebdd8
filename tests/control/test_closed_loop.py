"""Closed-loop execution in the MuJoCo world, with hand-written map programs (no LLM)."""

import numpy as np
import pytest

from tests.perceive import perceive
from voxposer.control import ClosedLoopController, ExecutorConfig
from voxposer.envs import TabletopWorld
from voxposer.envs.layout import SceneLayout
from voxposer.errors import PlanningError
from voxposer.valuemaps import ValueMapAPI


def _layout(**poses: tuple[float, float]) -> SceneLayout:
    blocks = tuple(name.removesuffix("_block") for name in poses)
    return SceneLayout(
        blocks=blocks,
        poses={f"{b} block": p for b, p in zip(blocks, poses.values(), strict=True)},
        extra_blocks=(0, 0),
        extra_lines=(0, 0),
    )


def _api(world: TabletopWorld) -> ValueMapAPI:
    return ValueMapAPI(world.grid, lambda: world.get_ee_pose()[1], world.get_gripper_state)


def test_move_above_a_block_while_avoiding_another(world: TabletopWorld) -> None:
    world.reset(
        np.random.default_rng(0), _layout(blue_block=(0.0, -0.1), green_block=(-0.12, -0.2))
    )
    api, grid = _api(world), world.grid

    def affordance() -> np.ndarray:
        blue = perceive(world).detect("blue block")
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel(blue.position + [0, 0, 0.08]))] = 1
        return m

    def avoidance() -> np.ndarray:
        green = perceive(world).detect("green block")
        m = api.get_empty_avoidance_map()
        api.set_voxel_by_radius(m, grid.world_to_voxel(green.position), 10, 1)
        return m

    result = ClosedLoopController(world, perceive(world), np.random.default_rng(0))(
        lambda: perceive(world).detect("gripper"), affordance, avoidance
    )
    assert result.success, result.message
    goal = world.object_position("blue block") + [0, 0, 0.08]
    assert np.linalg.norm(world.get_ee_pose()[0] - goal) < 0.03
    green = world.object_position("green block")
    clearance = np.linalg.norm(np.asarray(result.trace) - green, axis=1).min()
    assert clearance > 0.08  # kept out of the 10 cm avoidance sphere (less the path tolerance)
    assert result.replans > 3 and result.replan_hz > 0


def test_push_a_block_to_a_target(world: TabletopWorld) -> None:
    world.reset(np.random.default_rng(1), _layout(blue_block=(-0.05, -0.1)))
    api, grid = _api(world), world.grid
    goal = np.array([0.10, 0.02, 0.025])

    def affordance() -> np.ndarray:
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel(goal))] = 1
        return m

    start = world.object_position("blue block")
    result = ClosedLoopController(world, perceive(world), np.random.default_rng(1))(
        lambda: perceive(world).detect("blue block"), affordance
    )
    end = world.object_position("blue block")
    assert result.success, result.message
    assert np.linalg.norm(end[:2] - goal[:2]) < 0.05
    assert np.linalg.norm(end[:2] - start[:2]) > 0.15  # it really moved


def test_displaced_target_is_followed_in_closed_loop(world: TabletopWorld) -> None:
    world.reset(np.random.default_rng(2), _layout(blue_block=(0.05, 0.0)))
    api, grid = _api(world), world.grid

    def affordance() -> np.ndarray:
        blue = perceive(world).detect("blue block")
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel(blue.position + [0, 0, 0.06]))] = 1
        return m

    executor = ClosedLoopController(world, perceive(world), np.random.default_rng(2))
    moved = []

    def disturb(result, plan) -> None:
        if result.replans == 3 and not moved:
            moved.append(world.displace_object(np.random.default_rng(7), "blue block"))

    executor.on_replan = disturb
    result = executor(lambda: perceive(world).detect("gripper"), affordance)
    assert moved, "the disturbance was applied"
    assert result.success, result.message
    goal = world.object_position("blue block") + [0, 0, 0.06]
    assert np.linalg.norm(world.get_ee_pose()[0] - goal) < 0.03


def test_missing_affordance_and_unreachable_targets_end_with_a_reason(world: TabletopWorld) -> None:
    world.reset(np.random.default_rng(3), _layout(blue_block=(0.0, 0.0)))
    # the hand's floor off: with it a target under the table top is raised above the table
    # (test_a_hand_sent_onto_the_table_aims_above_it)
    executor = ClosedLoopController(world, perceive(world), np.random.default_rng(3),
                                    ExecutorConfig(max_time_s=3.0, hand_floor_m=0.0))
    with pytest.raises(PlanningError, match="needs an affordance_map"):
        executor(lambda: perceive(world).detect("gripper"))
    api = _api(world)
    grid = world.grid

    def inside_table() -> np.ndarray:  # under the table top: the hand cannot get there
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel([0.0, 0.0, -0.015]))] = 1
        return m

    result = executor(lambda: perceive(world).detect("gripper"), inside_table)
    assert not result.success and result.reason in ("planning_failed", "stalled", "timeout")
    assert "target" in result.message

    def out_of_reach() -> np.ndarray:  # free space, but 1.3 m from the robot's base
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel([0.29, 0.49, 0.9]))] = 1
        return m

    result = executor(lambda: perceive(world).detect("gripper"), out_of_reach)
    assert not result.success and result.reason in ("stalled", "timeout")
    assert "cm from the target" in result.message


def test_close_a_drawer_by_pushing_its_handle(world: TabletopWorld) -> None:
    layout = SceneLayout(blocks=("blue",), drawer_openings={"top": 0.15}, extra_blocks=(0, 0))
    world.reset(np.random.default_rng(4), layout)
    api, grid = _api(world), world.grid
    closed = perceive(world).detect("top drawer handle").position - 0.15 * world.drawer_axis("top drawer")

    def affordance() -> np.ndarray:
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel(closed))] = 1
        return m

    result = ClosedLoopController(world, perceive(world), np.random.default_rng(4))(
        lambda: perceive(world).detect("top drawer handle"), affordance
    )
    assert result.success, result.message
    assert world.drawer_opening("top") < 0.02


def test_a_grasped_block_is_carried_not_pushed_and_released_in_place(world: TabletopWorld) -> None:
    world.reset(np.random.default_rng(5), _layout(blue_block=(-0.1, 0.0)))
    api, grid = _api(world), world.grid
    executor = ClosedLoopController(world, perceive(world), np.random.default_rng(5))

    def at(point: np.ndarray) -> np.ndarray:
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel(point))] = 1
        return m

    def block_centre() -> np.ndarray:
        return at(perceive(world).detect("blue block").position)

    def grasp_gripper() -> np.ndarray:  # open, except close around the block
        m = api.get_empty_gripper_map()
        m[:] = 0
        return api.set_voxel_by_radius(m, grid.world_to_voxel(perceive(world).detect("blue block").position), 1, 1)

    top_down = api.get_empty_rotation_map()
    top_down[:] = api.pointat2quat([0, 0, -1])
    assert executor(lambda: perceive(world).detect("gripper"), block_centre, rotation_map=top_down,
                    gripper_map=grasp_gripper).success
    assert world.get_gripper_state() >= 0.5

    goal = np.array([0.0, -0.15, 0.12])  # 15 cm left and up: the hand must carry it there
    result = executor(lambda: perceive(world).detect("blue block"), lambda: at(goal))
    assert result.success, result.message
    assert result.trace, "carried with the hand (end-effector mode), not pushed"
    assert np.linalg.norm(world.object_position("blue block") - goal) < 0.04

    def open_gripper() -> np.ndarray:
        m = api.get_empty_gripper_map()
        m[:] = 0
        return m

    result = executor(lambda: perceive(world).detect("blue block"), block_centre, gripper_map=open_gripper)
    assert result.success, result.message
    assert world.get_gripper_state() < 0.5


def test_moves_that_miss_their_targets_are_reported_not_dropped(world: TabletopWorld,
                                                                 monkeypatch) -> None:
    """Every push move the world reports as missed is counted in the sub-task result and its
    message (the arm here is a test double's: the real moves, reported 3 cm off)."""
    import dataclasses

    world.reset(np.random.default_rng(1), _layout(blue_block=(-0.05, -0.1)))
    api, grid = _api(world), world.grid
    goal = np.array([0.05, -0.1, 0.025])
    real_move = world.move_to_pose
    calls = []

    def reported_off(*args, **kwargs):
        calls.append(args[0])
        return dataclasses.replace(real_move(*args, **kwargs), reached=False, position_error=0.03)

    monkeypatch.setattr(world, "move_to_pose", reported_off)

    def affordance() -> np.ndarray:
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel(goal))] = 1
        return m

    result = ClosedLoopController(world, perceive(world), np.random.default_rng(1), ExecutorConfig(max_time_s=20))(
        lambda: perceive(world).detect("blue block"), affordance
    )
    assert calls and result.missed_moves == len(calls)  # five moves per push, every one counted
    assert result.worst_miss_m == pytest.approx(0.03)
    assert f"{len(calls)} of the robot's moves ended away from their targets" in result.message


def test_a_hand_sent_onto_the_table_aims_above_it(world: TabletopWorld) -> None:
    """A point on the table's surface (a place named without a height) is raised to the hand's
    floor, 2 cm above the table: the hand aims there instead of at the surface, where its finger
    pads would drag (stalling short when it comes in low from the side); with the floor off the
    target stays on the table."""
    api, grid = _api(world), world.grid

    def on_table() -> np.ndarray:
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel([-0.38, 0.0, 0.0]))] = 1
        return m

    targets = []
    for floor in (0.02, 0.0):
        world.reset(np.random.default_rng(0), _layout(blue_block=(0.05, -0.25)))
        result = ClosedLoopController(world, perceive(world), np.random.default_rng(0),
                                      ExecutorConfig(hand_floor_m=floor))(
            lambda: perceive(world).detect("gripper"), on_table)
        assert result.success, result.message
        assert np.linalg.norm(world.get_ee_pose()[0][:2] - [-0.38, 0.0]) < 0.03
        targets.append(result.last_plan.target)
    raised, surface = targets
    assert 0.02 <= raised[2] <= 0.035 and surface[2] < 0.01
    with pytest.raises(Exception, match="hand_floor_m"):
        ExecutorConfig(hand_floor_m=-0.01)
