"""End-effector pose controller of the simulated Panda (App. A.5).

A desired 6-DoF end-effector pose becomes a stream of interpolated waypoints (straight line in
position, slerp in orientation, at the configured speed times ``speed_scale``); each waypoint is
solved by warm-started IK into joint positions, which the joint position servos follow. Per
waypoint the commanded joints also move at most ``max_joint_speed * speed_scale * control_dt``.

This module is physics-free: :class:`PoseController` produces joint commands; the world steps
the simulation with them. Quaternions are MuJoCo's (w, x, y, z) here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation, Slerp

from voxposer.envs.config import ControllerConfig
from voxposer.envs.ik import IKResult, IKSolver, rotation_angle
from voxposer.geometry.frames import wxyz_to_xyzw, xyzw_to_wxyz


@dataclass(frozen=True)
class Waypoint:
    """One controller period's command.

    Attributes:
        q: commanded arm joint positions [rad], shape (7,).
        position: the reference end-effector position [m], shape (3,).
        quat_wxyz: the reference orientation (w, x, y, z).
        at_goal: the reference has reached the goal pose.
        tracking_error: IK residual of this waypoint [m] (position).
    """

    q: NDArray[np.float64]
    position: NDArray[np.float64]
    quat_wxyz: NDArray[np.float64]
    at_goal: bool
    tracking_error: float


class PoseController:
    """Interpolates toward a goal pose and solves each waypoint with warm-started IK.

    Args:
        ik: the solver (owns the robot-only model).
        cfg: speeds, tolerances and control period.
    """

    def __init__(self, ik: IKSolver, cfg: ControllerConfig) -> None:
        self.ik = ik
        self.cfg = cfg
        self.q_cmd = np.zeros(7)
        self.ref_pos = np.zeros(3)
        self.ref_quat = np.array([1.0, 0.0, 0.0, 0.0])

    def reset(self, q: NDArray[np.float64]) -> None:
        """Restart from the joint configuration ``q`` [rad], shape (7,)."""
        self.q_cmd = np.array(q, dtype=np.float64)
        self.ref_pos, self.ref_quat = self.ik.forward(self.q_cmd)

    def solve_goal(self, pos: NDArray[np.float64], quat_wxyz: NDArray[np.float64],
                   rng: np.random.Generator) -> IKResult:
        """One-off IK of a goal pose: warm start from the command, then random restarts."""
        return self.ik.solve(pos, quat_wxyz, self.q_cmd, iterations=self.cfg.ik_iterations,
                             restarts=self.cfg.ik_restarts, rng=rng)

    def _joint_step_limit(self, speed_scale: float) -> float:
        return self.cfg.max_joint_speed * speed_scale * self.cfg.control_dt

    def next_waypoint(self, pos: NDArray[np.float64], quat_wxyz: NDArray[np.float64],
                      speed_scale: float = 1.0) -> Waypoint:
        """Advance the reference one control period toward the goal and solve it.

        Args:
            pos: goal position [m], shape (3,).
            quat_wxyz: goal orientation (w, x, y, z), unit norm.
            speed_scale: multiplies the end-effector linear and angular speeds (> 0).
        """
        dt = self.cfg.control_dt
        step = self.cfg.ee_speed * speed_scale * dt
        delta = pos - self.ref_pos
        dist = float(np.linalg.norm(delta))
        angle = rotation_angle(self.ref_quat, quat_wxyz)
        max_angle = self.cfg.ee_angular_speed * speed_scale * dt
        # Move position and orientation in lockstep so both arrive together.
        frac = 1.0 if dist <= step and angle <= max_angle else min(
            step / dist if dist > 0 else 1.0, max_angle / angle if angle > 0 else 1.0)
        self.ref_pos = pos.copy() if frac >= 1.0 else self.ref_pos + frac * delta
        if frac >= 1.0 or angle == 0.0:
            self.ref_quat = np.asarray(quat_wxyz, dtype=np.float64).copy()
        else:
            rots = Rotation.from_quat(np.stack([wxyz_to_xyzw(self.ref_quat), wxyz_to_xyzw(quat_wxyz)]))
            self.ref_quat = xyzw_to_wxyz(Slerp([0.0, 1.0], rots)(frac).as_quat())
        result = self.ik.solve(self.ref_pos, self.ref_quat, self.q_cmd, iterations=4)
        self._apply(result.q, speed_scale)
        return Waypoint(self.q_cmd.copy(), self.ref_pos.copy(), self.ref_quat.copy(), frac >= 1.0,
                        result.position_error)

    def joint_step(self, q_goal: NDArray[np.float64], speed_scale: float = 1.0) -> bool:
        """Move the command one period toward ``q_goal`` in joint space; True once there."""
        self._apply(q_goal, speed_scale)
        self.ref_pos, self.ref_quat = self.ik.forward(self.q_cmd)
        return bool(np.allclose(self.q_cmd, q_goal, atol=1e-6))

    def joint_path(self, q_goal: NDArray[np.float64], speed_scale: float = 1.0) -> NDArray[np.float64]:
        """The commands :meth:`joint_step` would give on its way to ``q_goal``, one per period
        [rad], shape (N, 7); the controller does not move."""
        limit = self._joint_step_limit(speed_scale)
        q, path = self.q_cmd.copy(), list[NDArray[np.float64]]()
        while not np.allclose(q, q_goal, atol=1e-6) and len(path) < 100_000:
            q = self._stepped(q, q_goal, limit)
            path.append(q)
        return np.array(path).reshape(-1, len(q))

    def _stepped(self, q: NDArray[np.float64], q_target: NDArray[np.float64], limit: float
                 ) -> NDArray[np.float64]:
        """``q`` moved at most ``limit`` [rad] per joint toward ``q_target``, within the limits."""
        return np.clip(q + np.clip(q_target - q, -limit, limit), self.ik.lower, self.ik.upper)

    def _apply(self, q_target: NDArray[np.float64], speed_scale: float) -> None:
        self.q_cmd = self._stepped(self.q_cmd, q_target, self._joint_step_limit(speed_scale))
