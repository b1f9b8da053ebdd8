"""The simulated Panda as a :class:`voxposer.robot.Robot`: its state and its pose control.

Mixins shared by every MuJoCo world that holds the Panda attached with
:func:`~voxposer.envs.robot_model.add_panda` (the tabletop :class:`~voxposer.envs.world.TabletopWorld`,
the articulated scenes of :mod:`voxposer.envs.articulated`). A world calls :meth:`ArmControlMixin._bind_arm`
once its model and data exist, and implements ``advance(nsteps)`` (its physics step).

Public quaternions are scalar-last (x, y, z, w); the end-effector's approach axis is its local +z.
"""

from __future__ import annotations

import logging
from typing import Protocol

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.envs.actions import check_command
from voxposer.envs.config import ControllerConfig
from voxposer.envs.controller import PoseController
from voxposer.envs.ik import HOME_Q, IKSolver, rotation_angle
from voxposer.envs.robot_model import (
    ARM_ACTUATORS,
    ARM_JOINTS,
    EE_SITE,
    FINGER_ACTUATORS,
    FINGER_JOINTS,
    FINGER_OPEN,
)
from voxposer.errors import UnreachablePoseError
from voxposer.geometry.frames import wxyz_to_xyzw, xyzw_to_wxyz
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.robot import MoveResult, StepResult

log = logging.getLogger(__name__)


class ArmSettings(Protocol):
    """What the arm reads of its world's configuration (``WorldConfig`` and the like)."""

    @property
    def robot_base(self) -> tuple[float, float, float]:
        """Position of the robot base [m], shape (3,)."""
        ...

    @property
    def timestep(self) -> float:
        """Physics step [s]."""
        ...

    @property
    def controller(self) -> ControllerConfig:
        """Pose controller settings."""
        ...

    @property
    def substeps(self) -> int:
        """Physics steps per controller period."""
        ...


class ArmStateMixin:
    """The arm's state queries (needs the attributes declared below)."""

    config: ArmSettings
    model: mujoco.MjModel
    data: mujoco.MjData
    _gripper: float
    _ee_site: int
    _finger_qpos: NDArray[np.int64]
    _arm_qpos: NDArray[np.int64]

    @property
    def control_period(self) -> float:
        """Duration of one :meth:`step` [s] (``ControllerConfig.control_dt``)."""
        return float(self.config.controller.control_dt)

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return float(self.data.time)

    @property
    def ee_speed(self) -> float:
        """End-effector linear speed at ``speed_scale=1`` [m/s] (``ControllerConfig.ee_speed``)."""
        return float(self.config.controller.ee_speed)

    @property
    def base_position(self) -> NDArray[np.float64]:
        """Position of the robot's base [m], shape (3,)."""
        return np.asarray(self.config.robot_base, dtype=np.float64)

    def joint_positions(self) -> NDArray[np.float64]:
        """The seven arm joint angles [rad], shape (7,)."""
        return np.asarray(self.data.qpos[self._arm_qpos], dtype=np.float64).copy()

    def get_ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """End-effector position [m], shape (3,), and orientation (x, y, z, w)."""
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, self.data.site_xmat[self._ee_site])
        return self.data.site_xpos[self._ee_site].copy(), wxyz_to_xyzw(quat)

    def get_gripper_state(self) -> float:
        """Commanded gripper state: 1.0 closed, 0.0 open."""
        return self._gripper

    def gripper_opening(self) -> float:
        """Measured distance between the fingers [m] (0 closed, 0.08 fully open)."""
        q = self.data.qpos[self._finger_qpos]
        return float(q[0] - q[1])


class ArmControlMixin(ArmStateMixin):
    """End-effector pose control of the Panda (App. A.5): IK → joint waypoints → joint servos."""

    grid: VoxelGrid
    ik: IKSolver
    controller: PoseController
    _rng: np.random.Generator
    _arm_dof: NDArray[np.int64]
    _arm_act: NDArray[np.int64]
    _finger_act: NDArray[np.int64]

    def advance(self, nsteps: int) -> None:
        """Step the physics ``nsteps`` times with the current commands (the world implements it)."""
        raise NotImplementedError

    def _bind_arm(self) -> None:
        """Create the IK solver and controller and look up the Panda's joints, actuators, site."""
        ctl = self.config.controller
        self.ik = IKSolver(self.config.robot_base, ctl.position_tolerance, ctl.rotation_tolerance)
        self.controller = PoseController(self.ik, ctl)
        m = self.model
        self._arm_qpos = np.array([m.joint(j).qposadr[0] for j in ARM_JOINTS])
        self._arm_dof = np.array([m.joint(j).dofadr[0] for j in ARM_JOINTS])
        self._finger_qpos = np.array([m.joint(j).qposadr[0] for j in FINGER_JOINTS])
        self._arm_act = np.array([m.actuator(a).id for a in ARM_ACTUATORS])
        self._finger_act = np.array([m.actuator(a).id for a in FINGER_ACTUATORS])
        self._ee_site = m.site(EE_SITE).id

    def _set_gripper(self, gripper: float | None) -> bool:
        if gripper is None or (gripper >= 0.5) == (self._gripper >= 0.5):
            return False
        self._gripper = 1.0 if gripper >= 0.5 else 0.0
        opening = 0.0 if self._gripper else FINGER_OPEN
        self.data.ctrl[self._finger_act] = (opening, -opening)
        return True

    def step(self, position: ArrayLike, quat_xyzw: ArrayLike, gripper: float | None = None,
             speed_scale: float = 1.0) -> StepResult:
        """Execute one controller period (``control_dt``) toward an end-effector pose.

        The reference moves at most ``ee_speed * speed_scale * control_dt`` toward the target;
        this is the cheap building block of closed-loop execution (one waypoint per call).
        """
        cmd = check_command(position, quat_xyzw, gripper, speed_scale, grid=self.grid,
                            max_speed_scale=self.config.controller.max_speed_scale)
        self._set_gripper(cmd.gripper)
        wp = self.controller.next_waypoint(cmd.position, xyzw_to_wxyz(cmd.quat_xyzw), cmd.speed_scale)
        self.data.ctrl[self._arm_act] = wp.q
        self.advance(self.config.substeps)
        return StepResult(self.data.site_xpos[self._ee_site].copy(), wp.at_goal, float(self.data.time))

    def move_to_pose(self, position: ArrayLike, quat_xyzw: ArrayLike | None = None,
                     speed_scale: float = 1.0, gripper: float | None = None,
                     max_detour: float | None = None) -> MoveResult:
        """Move the end-effector to a pose and wait until it arrives (or ``settle_time`` passes).

        The hand follows the straight line to the target (IK at each waypoint). Where that line
        cannot be followed (a joint limit, the arm folded in front of its base), the move is
        finished in joint space toward the goal configuration, a path the hand does not keep
        to: unless that path would take the hand farther than ``max_detour`` from the line, in
        which case the move ends where the line got stuck (``reached`` False).

        Args:
            position: target [m], shape (3,).
            quat_xyzw: target orientation (x, y, z, w); None keeps the current one.
            speed_scale: multiplies the default end-effector speed.
            gripper: 1 to close or 0 to open once the pose is reached; None leaves it.
            max_detour: [m] see above; None: no limit.

        Raises:
            UnreachablePoseError: no joint configuration reaches the pose (with the closest
                reachable position/orientation error); the robot does not move.
            InvalidActionError: NaN or out-of-range arguments.
        """
        quat = self.get_ee_pose()[1] if quat_xyzw is None else quat_xyzw
        cmd = check_command(position, quat, gripper, speed_scale, grid=self.grid,
                            max_speed_scale=self.config.controller.max_speed_scale)
        target_q = xyzw_to_wxyz(cmd.quat_xyzw)
        goal = self.controller.solve_goal(cmd.position, target_q, self._rng)
        if not goal.success:
            raise UnreachablePoseError(np.round(cmd.position, 4).tolist(), goal.position_error,
                                       goal.rotation_error)
        ctl = self.config.controller
        start = float(self.data.time)
        catch_up = round(ctl.settle_time / ctl.control_dt)
        for _ in range(100_000):
            before = self.controller.q_cmd.copy()
            wp = self.controller.next_waypoint(cmd.position, target_q, cmd.speed_scale)
            self.data.ctrl[self._arm_act] = wp.q
            self.advance(self.config.substeps)
            # the reference arrives first; the command may still lag it (joint-speed clamp)
            if wp.at_goal and (catch_up <= 0 or np.abs(wp.q - before).max() < 1e-4):
                break
            catch_up -= int(wp.at_goal)
        cmd_err = float(np.linalg.norm(self.ik.forward(self.controller.q_cmd)[0] - cmd.position))
        if not np.allclose(self.controller.q_cmd, goal.q, atol=0.05) and (
                wp.tracking_error > ctl.position_tolerance or cmd_err > ctl.position_tolerance):
            self._finish_in_joint_space(goal.q, cmd.position, cmd.speed_scale, max_detour, cmd_err)
        settle_end = float(self.data.time) + ctl.settle_time
        while float(self.data.time) < settle_end:
            pos_err, rot_err = self._pose_error(cmd.position, target_q)
            if pos_err <= ctl.position_tolerance and rot_err <= ctl.rotation_tolerance:
                break
            self.advance(self.config.substeps)
        if self._set_gripper(cmd.gripper):
            self.advance(round(ctl.gripper_time / self.config.timestep))
        pos_err, rot_err = self._pose_error(cmd.position, target_q)
        reached = pos_err <= 2 * ctl.position_tolerance and rot_err <= 2 * ctl.rotation_tolerance
        if not reached:
            log.warning("move_to_pose ended %.1f cm / %.3f rad from its target (blocked?)",
                        pos_err * 100, rot_err)
        return MoveResult(reached, pos_err, rot_err, float(self.data.time) - start)

    def _finish_in_joint_space(self, q_goal: NDArray[np.float64], target: NDArray[np.float64],
                               speed_scale: float, max_detour: float | None, short: float) -> None:
        """Where the straight line got stuck (``short`` [m] from ``target``), move in joint space
        to ``q_goal``, unless the hand would pass farther than ``max_detour`` [m] from the line
        between here and the target."""
        if max_detour is not None:
            here = self.ik.forward(self.controller.q_cmd)[0]
            hand = np.array([self.ik.forward(q)[0] for q in self.controller.joint_path(q_goal, speed_scale)])
            detour = _distance_to_segment(hand.reshape(-1, 3), here, target)
            if detour > max_detour:
                log.debug("straight-line IK got stuck %.3f m short; the move ends there (a "
                          "joint-space finish would pass %.3f m off the line)", short, detour)
                return
        log.debug("straight-line IK got stuck %.3f m short; finishing in joint space", short)
        while not self.controller.joint_step(q_goal, speed_scale):
            self.data.ctrl[self._arm_act] = self.controller.q_cmd
            self.advance(self.config.substeps)
        self.data.ctrl[self._arm_act] = self.controller.q_cmd

    def _pose_error(self, pos: NDArray[np.float64], quat_wxyz: NDArray[np.float64]) -> tuple[float, float]:
        here = np.zeros(4)
        mujoco.mju_mat2Quat(here, self.data.site_xmat[self._ee_site])
        return (float(np.linalg.norm(self.data.site_xpos[self._ee_site] - pos)),
                rotation_angle(here, quat_wxyz))

    def _actuate_gripper(self, gripper: float) -> None:
        if self._set_gripper(gripper):
            self.data.ctrl[self._arm_act] = self.controller.q_cmd
            self.advance(round(self.config.controller.gripper_time / self.config.timestep))

    def open_gripper(self) -> None:
        """Open the fingers (and wait ``gripper_time`` while the arm holds its pose)."""
        self._actuate_gripper(0.0)

    def close_gripper(self) -> None:
        """Close the fingers (and wait ``gripper_time`` while the arm holds its pose)."""
        self._actuate_gripper(1.0)

    def reset_to_default_pose(self, speed_scale: float = 1.0) -> MoveResult:
        """Move back to the ready pose (the paper's ``reset_to_default_pose``)."""
        pos, quat = self.ik.forward(HOME_Q)
        return self.move_to_pose(pos, wxyz_to_xyzw(quat), speed_scale)


def _distance_to_segment(points: NDArray[np.float64], a: NDArray[np.float64],
                         b: NDArray[np.float64]) -> float:
    """Largest distance of ``points`` [m], shape (N, 3), from the segment a–b; 0 for none."""
    if len(points) == 0:
        return 0.0
    ab = b - a
    t = np.clip((points - a) @ ab / max(float(ab @ ab), 1e-12), 0.0, 1.0)
    return float(np.linalg.norm(points - (a + t[:, None] * ab), axis=1).max())


__all__ = ["ArmControlMixin", "ArmSettings", "ArmStateMixin"]
