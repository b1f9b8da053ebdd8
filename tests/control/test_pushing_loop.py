import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from voxposer.control.pushing_loop import MID_WRIST_YAW, top_down_quat
from voxposer.planning.push_primitive import PushAction
from voxposer.valuemaps import TOP_DOWN_QUAT


def _finger_axis(quat_xyzw: np.ndarray) -> np.ndarray:
    return Rotation.from_quat(quat_xyzw).apply([1.0, 0.0, 0.0])  # fingers close along local x


def _yaw(quat_xyzw: np.ndarray) -> float:
    rel = Rotation.from_quat(quat_xyzw) * Rotation.from_quat(TOP_DOWN_QUAT).inv()
    return float(rel.as_rotvec()[2])


def test_finger_axis_along_world_y_at_the_ready_pose_is_the_top_down_quaternion() -> None:
    np.testing.assert_allclose(top_down_quat(np.array([0.0, 1.0, 0.0])), TOP_DOWN_QUAT, atol=1e-9)
    np.testing.assert_allclose(np.abs(_finger_axis(np.array(TOP_DOWN_QUAT))), [0, 1, 0], atol=1e-9)


@pytest.mark.parametrize("angle", [0.0, 0.4, 1.2, 2.0, -2.7])
@pytest.mark.parametrize("azimuth", [-0.9, 0.0, 0.6])
def test_hand_points_down_with_its_fingers_along_the_axis_and_the_wrist_mid_range(
    angle: float, azimuth: float
) -> None:
    axis = np.array([np.cos(angle), np.sin(angle), 0.0])
    q = top_down_quat(axis, azimuth)
    np.testing.assert_allclose(Rotation.from_quat(q).apply([0, 0, 1]), [0, 0, -1], atol=1e-9)
    assert abs(_finger_axis(q) @ axis) == pytest.approx(1.0, abs=1e-9)
    # of the two equivalent yaws, the one within a quarter turn of the wrist's mid-range
    off = (_yaw(q) - azimuth - MID_WRIST_YAW + np.pi) % (2 * np.pi) - np.pi
    assert abs(off) <= np.pi / 2 + 1e-9


def _push_along_x(contact_y: float) -> PushAction:
    return PushAction(np.array([-0.1, contact_y, 0.02]), np.array([1.0, 0.0, 0.0]), 0.05,
                      np.array([-0.05, contact_y, 0.02]), 0.0, np.array([0.0, 1.0, 0.0]))


def test_a_push_whose_approach_misses_goes_straight_up_instead_of_through() -> None:
    """The hand cannot reach behind the contact (a wall at y = 0.05 stands in for a pose the
    arm cannot take): it must not sweep "through" from where it got stuck."""
    from tests.control.test_seams import KinematicRobot
    from voxposer.control.pushing_loop import APPROACH_MISS_M, push

    robot = KinematicRobot((-0.3, 0.0, 0.15), wall_y=0.05)
    moves = push(robot, _push_along_x(0.10), sideways=False, object_top=0.05)
    assert len(moves) == 2 and moves[0].position_error > APPROACH_MISS_M
    assert robot.position[0] < -0.1, "the hand never passed the contact point"
    assert robot.position[2] >= 0.05 + 0.03 - 1e-6, "it went up, not through"

    free = KinematicRobot((-0.3, 0.0, 0.15))
    assert len(push(free, _push_along_x(0.10), sideways=False, object_top=0.05)) == 5
    assert free.position[0] > -0.1, "a reachable push goes through"


def test_the_stroke_the_retreat_and_the_lift_keep_to_their_straight_lines() -> None:
    """Finishing a stuck stroke in joint space swept the hand across the table (into the block
    to stay away from); those moves ask the robot to stay on their lines."""
    from tests.control.test_seams import KinematicRobot
    from voxposer.control.pushing_loop import push

    robot = KinematicRobot((-0.3, 0.0, 0.15))
    asked: list[float | None] = []
    move = robot.move_to_pose

    def recording(position, quat_xyzw=None, speed_scale=1.0, gripper=None, max_detour=None):
        asked.append(max_detour)
        return move(position, quat_xyzw, speed_scale, gripper, max_detour)

    robot.move_to_pose = recording  # type: ignore[method-assign]
    push(robot, _push_along_x(0.10), sideways=False, object_top=0.05)
    assert asked[0] is None  # the move above the contact, at the travel height
    assert all(d is not None and d <= 0.03 for d in asked[2:]) and len(asked) == 5
