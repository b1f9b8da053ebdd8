"""The fridge's magnetic seal: a pull below ``seal_force`` keeps the door shut, a stronger one
opens it, the robot pulling its handle along the door's arc opens it, and the seal snaps a nearly
shut door closed. The handle is gripped with real finger contacts."""

import math

import numpy as np
from scipy.spatial.transform import Rotation
from tests.envs.articulated.articulated_motions import grasp_handle, push_part, turn_grip

from voxposer.envs.articulated import ArticulatedWorld


def _outward(world: ArticulatedWorld) -> np.ndarray:
    """The shut door's outward normal (toward the robot), shape (3,)."""
    assert world.placement is not None
    return Rotation.from_euler("z", world.placement.object_yaw).apply([-1.0, 0.0, 0.0])


def test_a_pull_below_the_seal_force_keeps_the_door_shut(fridge: ArticulatedWorld) -> None:
    weak = 0.8 * fridge.config.fridge.seal_force
    push_part(fridge, "fridge handle", weak * _outward(fridge), seconds=1.0)
    assert fridge.articulation_state()["door_angle"] < math.radians(1.0)


def test_a_pull_above_the_seal_force_opens_the_door(fridge: ArticulatedWorld) -> None:
    strong = 1.3 * fridge.config.fridge.seal_force
    push_part(fridge, "fridge handle", strong * _outward(fridge), seconds=1.0)
    assert fridge.articulation_state()["door_angle"] > 2 * fridge.config.fridge.seal_range


def test_pulling_the_handle_along_the_arc_opens_the_fridge(fridge: ArticulatedWorld) -> None:
    pose = grasp_handle(fridge)
    assert fridge.gripper_opening() > 0.015  # the fingers closed on the bar
    turn_grip(fridge, "door_angle", pose, 36.0, step=3.0)
    ok, reason = fridge.success()
    assert ok, reason


def test_the_seal_pulls_a_nearly_shut_door_closed(fridge: ArticulatedWorld) -> None:
    fridge.set_articulation_state({"door_angle": 0.7 * fridge.config.fridge.seal_range})
    fridge.advance(round(1.0 / fridge.config.timestep))
    assert fridge.articulation_state()["door_angle"] < math.radians(0.2)
