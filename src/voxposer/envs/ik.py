"""Inverse kinematics of the Panda's end-effector site with mink, on a robot-only model.

The solver owns a 7-DoF model of the arm alone (no fingers, no scene), so nothing but the arm's
joints can move and joint limits are respected by mink's :class:`~mink.ConfigurationLimit`.
Poses here use MuJoCo's scalar-first quaternions (w, x, y, z); the public world API converts.
"""

from __future__ import annotations

from dataclasses import dataclass

import mink
import mujoco
import numpy as np
from numpy.typing import NDArray

from voxposer.envs.robot_model import EE_SITE, robot_only_model

#: The Panda's ready pose [rad]: gripper pointing down above the table.
HOME_Q: NDArray[np.float64] = np.array([0.0, -0.6, 0.0, -2.3, 0.0, 1.7, 0.785])
HOME_Q.flags.writeable = False


@dataclass(frozen=True)
class IKResult:
    """Outcome of an IK solve.

    Attributes:
        q: joint positions [rad], shape (7,): the best configuration found.
        position_error: distance [m] from its end-effector position to the target.
        rotation_error: angle [rad] between its end-effector orientation and the target.
        success: both errors are within the solver's tolerances.
        iterations: IK iterations used (over all restarts).
    """

    q: NDArray[np.float64]
    position_error: float
    rotation_error: float
    success: bool
    iterations: int


def rotation_angle(a_wxyz: NDArray[np.float64], b_wxyz: NDArray[np.float64]) -> float:
    """Angle [rad] of the rotation between two unit quaternions (w, x, y, z)."""
    dot = abs(float(np.dot(a_wxyz, b_wxyz)))
    return 2.0 * float(np.arccos(min(1.0, dot)))


class IKSolver:
    """Damped least-squares IK (mink + daqp) of :data:`EE_SITE` in world coordinates.

    Args:
        base_pos: robot base position [m], shape (3,), the same as in the scene.
        position_tolerance: success threshold on position error [m].
        rotation_tolerance: success threshold on orientation error [rad].
    """

    def __init__(
        self,
        base_pos: tuple[float, float, float],
        position_tolerance: float = 0.005,
        rotation_tolerance: float = 0.035,
    ) -> None:
        self.model = robot_only_model(base_pos)
        self._conf = mink.Configuration(self.model)
        self._task = mink.FrameTask(EE_SITE, "site", position_cost=1.0, orientation_cost=0.5,
                                    lm_damping=1e-3)
        self._posture = mink.PostureTask(self.model, cost=2e-3)
        self._posture.set_target(HOME_Q)
        self._limits = [mink.ConfigurationLimit(self.model, gain=0.95)]
        self._site = self.model.site(EE_SITE).id
        self.lower = self.model.jnt_range[:, 0].copy()
        self.upper = self.model.jnt_range[:, 1].copy()
        self.position_tolerance = position_tolerance
        self.rotation_tolerance = rotation_tolerance
        self._quat = np.zeros(4)

    def forward(self, q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """End-effector position [m], shape (3,), and quaternion (w, x, y, z) at joints ``q``."""
        self._conf.update(np.clip(q, self.lower, self.upper))
        return self._ee()

    def _ee(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        data = self._conf.data
        mujoco.mju_mat2Quat(self._quat, data.site_xmat[self._site])
        return data.site_xpos[self._site].copy(), self._quat.copy()

    def _errors(self, pos: NDArray[np.float64], quat: NDArray[np.float64]) -> tuple[float, float]:
        p, q = self._ee()
        return float(np.linalg.norm(p - pos)), rotation_angle(q, quat)

    def _descend(self, pos: NDArray[np.float64], quat: NDArray[np.float64], q0: NDArray[np.float64],
                 iterations: int) -> tuple[NDArray[np.float64], float, float, int]:
        self._conf.update(np.clip(q0, self.lower + 1e-6, self.upper - 1e-6))
        errors = self._errors(pos, quat)
        used = 0
        for used in range(1, iterations + 1):
            if errors[0] <= self.position_tolerance * 0.2 and errors[1] <= self.rotation_tolerance * 0.2:
                used -= 1
                break
            vel = mink.solve_ik(self._conf, [self._task, self._posture], 1.0, "daqp",
                                damping=1e-4, limits=self._limits)
            self._conf.integrate_inplace(vel, 1.0)
            errors = self._errors(pos, quat)
        return self._conf.q.copy(), errors[0], errors[1], used

    def solve(
        self,
        pos: NDArray[np.float64],
        quat_wxyz: NDArray[np.float64],
        q_init: NDArray[np.float64],
        *,
        iterations: int = 40,
        restarts: int = 0,
        rng: np.random.Generator | None = None,
    ) -> IKResult:
        """Joint positions that put the end-effector site at ``pos`` with orientation ``quat_wxyz``.

        Args:
            pos: target position [m], shape (3,).
            quat_wxyz: target orientation, unit quaternion (w, x, y, z).
            q_init: warm start [rad], shape (7,).
            iterations: IK iterations per attempt.
            restarts: extra attempts from random configurations drawn from ``rng`` when the
                warm start fails (a one-off target); 0 for cheap tracking of nearby waypoints.
            rng: the generator for restarts (required when ``restarts > 0``).
        """
        pos = np.asarray(pos, dtype=np.float64)
        quat = np.asarray(quat_wxyz, dtype=np.float64)
        self._task.set_target(mink.SE3.from_rotation_and_translation(mink.SO3(quat), pos))
        best = self._descend(pos, quat, np.asarray(q_init, dtype=np.float64), iterations)
        total = best[3]
        starts = [HOME_Q]
        if rng is not None:
            starts += [HOME_Q + rng.normal(0.0, 0.6, 7) if k % 2 else rng.uniform(self.lower, self.upper)
                       for k in range(restarts)]
        for q0 in starts[: restarts + (1 if restarts else 0)]:
            if self._ok(best):
                break
            attempt = self._descend(pos, quat, q0, iterations)
            total += attempt[3]
            if attempt[1] + 0.1 * attempt[2] < best[1] + 0.1 * best[2]:
                best = attempt
        return IKResult(best[0], best[1], best[2], self._ok(best), total)

    def _ok(self, attempt: tuple[NDArray[np.float64], float, float, int]) -> bool:
        return attempt[1] <= self.position_tolerance and attempt[2] <= self.rotation_tolerance
