"""The window: its sash stays put under a light touch (dry friction) and slides when the robot
pushes its knob sideways. The knob is gripped with real finger contacts."""

import numpy as np
from tests.envs.articulated.articulated_motions import grasp_handle, move_grip, push_part

from voxposer.envs.articulated import ArticulatedWorld


def test_a_light_touch_does_not_slide_the_sash(window: ArticulatedWorld) -> None:
    axis = window.joint_axis("window_offset").direction
    light = 0.5 * window.config.window.frictionloss
    push_part(window, "window handle", light * axis, seconds=1.0)
    assert window.articulation_state()["window_offset"] < 0.003
    assert not window.success()[0]


def test_a_force_above_the_friction_slides_it(window: ArticulatedWorld) -> None:
    axis = window.joint_axis("window_offset").direction
    push_part(window, "window handle", 2.0 * window.config.window.frictionloss * axis,
              seconds=1.0)
    assert window.articulation_state()["window_offset"] > 0.05


def test_pushing_the_knob_sideways_opens_the_window(window: ArticulatedWorld) -> None:
    pose = grasp_handle(window)
    assert window.gripper_opening() > 0.015  # the fingers closed on the knob
    axis = window.joint_axis("window_offset").direction
    move_grip(window, pose, 0.16 * axis)
    offset = window.articulation_state()["window_offset"]
    assert offset > window.config.window.success_offset
    ok, reason = window.success()
    assert ok, reason
    handle_moved = window.part_position("window handle") - pose[0]
    np.testing.assert_allclose(handle_moved @ axis, offset, atol=0.005)
