"""The door's latch: it holds against pulls until the lever is pressed past its angle; the lever
springs back; a shut door latches again. Grasps are real finger contacts."""

import math

import numpy as np
from scipy.spatial.transform import Rotation
from tests.envs.articulated.articulated_motions import grasp_handle, move_grip, turn_grip

from voxposer.envs.articulated import ArticulatedWorld
from voxposer.envs.articulated.door import Door


def _latched(world: ArticulatedWorld) -> bool:
    door = world.object
    assert isinstance(door, Door)
    return door.latched(world.model)


def _normal(world: ArticulatedWorld) -> np.ndarray:
    """The shut door's normal into the frame (away from the robot), shape (3,)."""
    assert world.placement is not None
    return Rotation.from_euler("z", world.placement.object_yaw).apply([1.0, 0.0, 0.0])


def _track_max_door_angle(world: ArticulatedWorld) -> list[float]:
    peak = [0.0]
    world.step_callbacks.append(
        lambda w: peak.__setitem__(0, max(peak[0], w.articulation_state()["door_angle"])))
    return peak


def test_latch_holds_a_straight_pull_without_the_lever(door: ArticulatedWorld) -> None:
    pose = grasp_handle(door)
    assert door.gripper_opening() > 0.015  # the fingers closed on the lever
    peak = _track_max_door_angle(door)
    try:
        move_grip(door, pose, -0.12 * _normal(door))
    finally:
        door.step_callbacks.clear()
    assert 0.5 * door.config.door.latch_play < peak[0] < math.radians(2.0)  # pulled to its stop
    assert door.articulation_state()["handle_angle"] < door.config.door.unlatch_angle
    assert not door.success()[0]


def test_latch_holds_a_pull_along_the_doors_arc(door: ArticulatedWorld) -> None:
    pose = grasp_handle(door)
    peak = _track_max_door_angle(door)
    try:
        turn_grip(door, "door_angle", pose, 20.0, step=4.0)
    finally:
        door.step_callbacks.clear()
    assert 0.5 * door.config.door.latch_play < peak[0] < math.radians(2.0)


def test_pressing_the_lever_then_pulling_opens_the_door(door: ArticulatedWorld) -> None:
    pose = grasp_handle(door)
    pressed = turn_grip(door, "handle_angle", pose, 40.0, step=5.0)
    state = door.articulation_state()
    assert state["handle_angle"] > door.config.door.unlatch_angle
    assert state["door_angle"] < math.radians(1.0)
    assert not _latched(door)
    turn_grip(door, "door_angle", pressed, 36.0, step=3.0)
    ok, reason = door.success()
    assert ok, reason
    assert door.articulation_state()["door_angle"] > door.config.door.success_angle


def test_released_lever_springs_back_and_keeps_the_door_latched(door: ArticulatedWorld) -> None:
    door.set_articulation_state({"handle_angle": math.radians(40.0)})
    assert not _latched(door)
    door.advance(round(1.0 / door.config.timestep))
    assert abs(door.articulation_state()["handle_angle"]) < math.radians(2.0)
    assert _latched(door)


def test_a_free_door_latches_again_when_shut(door: ArticulatedWorld) -> None:
    door.set_articulation_state({"door_angle": math.radians(10.0)})
    assert not _latched(door)
    door.advance(50)
    assert not _latched(door)  # lever up, but the door is out of the frame
    body = door.model.body("door").id
    door.data.xfrc_applied[body, :3] = 5.0 * _normal(door)  # push it shut
    door.advance(round(1.5 / door.config.timestep))
    door.data.xfrc_applied[body] = 0.0
    assert _latched(door)
    assert door.articulation_state()["door_angle"] <= door.config.door.latch_play + 1e-3
    assert door.articulation_state()["handle_angle"] < door.config.door.unlatch_angle
