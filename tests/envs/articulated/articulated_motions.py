"""Scripted motions of the articulated tests: grasp a handle with the Panda's fingers, then turn
or slide the grip about the ground-truth joint axis.

Grasps are real finger contacts (no weld). The door lever and the fridge handle (bars across
the door) are gripped from above and in front, the approach tilted 45° toward the door, with the
fingers closing along the door's normal (one finger between the bar and the door: a pull is
carried by that finger, not by friction). The window's knob is gripped from above, the approach
tilted 30° toward the window, with the fingers closing sideways (along the slide).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from voxposer.envs.articulated import ArticulatedWorld


def grasp_rotation(world: ArticulatedWorld) -> Rotation:
    """The gripper's orientation for grasping the object's handle (object yaw included)."""
    if world.task == "window":
        b = math.radians(30)
        local = np.column_stack([[0, 1, 0], [math.cos(b), 0, math.sin(b)],
                                 [math.sin(b), 0, -math.cos(b)]])
    else:
        a = math.radians(45)
        local = np.column_stack([[math.cos(a), 0, math.sin(a)], [0, -1, 0],
                                 [math.sin(a), 0, -math.cos(a)]])
    assert world.placement is not None
    return Rotation.from_euler("z", world.placement.object_yaw) * Rotation.from_matrix(local)


def handle_name(world: ArticulatedWorld) -> str:
    """The part the robot grasps."""
    return f"{world.task} handle"


def grasp_handle(world: ArticulatedWorld) -> tuple[np.ndarray, Rotation]:
    """Open, come in along the approach axis, close on the handle; returns the grip pose."""
    rot = grasp_rotation(world)
    grip = world.part_position(handle_name(world))
    approach = rot.apply([0.0, 0.0, 1.0])
    world.open_gripper()
    world.move_to_pose(grip - 0.10 * approach, rot.as_quat())
    follow(world, grip - 0.10 * approach, rot)  # finish the wrist's turn
    world.move_to_pose(grip, rot.as_quat(), speed_scale=0.5)
    follow(world, grip, rot)
    world.close_gripper()
    return grip, rot


def follow(world: ArticulatedWorld, position: np.ndarray, rot: Rotation, speed_scale: float = 0.5,
           max_steps: int = 60) -> None:
    """Step toward a pose until the hand is there (``move_to_pose`` stops when its reference
    arrives, which can leave the wrist behind when a joint is speed-limited; ``step`` goes on)."""
    quat = rot.as_quat()
    for _ in range(max_steps):
        result = world.step(position, quat, speed_scale=speed_scale)
        here, now = world.get_ee_pose()
        turn = (Rotation.from_quat(now).inv() * rot).magnitude()
        if result.at_goal and np.linalg.norm(here - position) < 0.004 and turn < 0.03:
            return


def turn_grip(world: ArticulatedWorld, key: str, pose: tuple[np.ndarray, Rotation],
              degrees: float, step: float = 2.0) -> tuple[np.ndarray, Rotation]:
    """Turn a grip pose about the joint behind ``key`` in steps of ``step`` degrees (the hand
    follows the part's arc); returns the final commanded pose."""
    axis = world.joint_axis(key)
    position, rot = pose
    target = (position, rot)
    for deg in np.arange(step, degrees + 1e-9, step):
        q = Rotation.from_rotvec(axis.direction * math.radians(float(deg)))
        target = (axis.anchor + q.apply(position - axis.anchor), q * rot)
        follow(world, *target)
    return target


def move_grip(world: ArticulatedWorld, pose: tuple[np.ndarray, Rotation],
              offset: np.ndarray, speed_scale: float = 0.5) -> None:
    """Move the hand by ``offset`` [m], shape (3,), from a grip pose, keeping its orientation."""
    position, rot = pose
    world.move_to_pose(position + np.asarray(offset), rot.as_quat(), speed_scale=speed_scale)


def push_part(world: ArticulatedWorld, part: str, force: np.ndarray, seconds: float) -> None:
    """Apply ``force`` [N], shape (3,), at a part's body for ``seconds`` [s] (robot holding)."""
    body = world.model.body(part.replace(" ", "_")).id
    world.data.xfrc_applied[body, :3] = force
    world.advance(round(seconds / world.config.timestep))
    world.data.xfrc_applied[body] = 0.0
