"""``TabletopWorld``: the simulated tabletop of the paper (App. A.5) behind one small facade.

Physics, control and cameras of the MuJoCo scene built by
:mod:`voxposer.envs.scene`. Public quaternions are scalar-last (x, y, z, w); the end-effector's
approach axis is its local +z (a top-down grasp points along world −z, :data:`TOP_DOWN_QUAT`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from voxposer.catalog import DRAWERS, OBJECTS
from voxposer.envs.actions import check_command
from voxposer.envs.config import WorldConfig
from voxposer.envs.controller import PoseController
from voxposer.envs.disturbances import DisturbanceMixin
from voxposer.envs.ik import HOME_Q, IKSolver, rotation_angle
from voxposer.envs.layout import Placement, SceneLayout, sample_placement
from voxposer.envs.registry import ObjectRegistry, body_of
from voxposer.envs.robot_model import (
    ARM_ACTUATORS,
    ARM_JOINTS,
    EE_SITE,
    FINGER_ACTUATORS,
    FINGER_JOINTS,
    FINGER_OPEN,
)
from voxposer.envs.scene import PARKING_Z, build_scene
from voxposer.envs.sensing import SensingMixin
from voxposer.errors import (
    LayoutError,
    SimulationUnstableError,
    UnreachablePoseError,
    VoxPoserError,
)
from voxposer.geometry.frames import TOP_DOWN_QUAT as _TOP_DOWN
from voxposer.geometry.frames import wxyz_to_xyzw, xyzw_to_wxyz
from voxposer.robot import MoveResult, StepResult

log = logging.getLogger(__name__)

#: Top-down end-effector orientation (x, y, z, w): approach axis along world −z, fingers along y.
TOP_DOWN_QUAT: NDArray[np.float64] = np.array(_TOP_DOWN)
TOP_DOWN_QUAT.flags.writeable = False


def _yaw_quat(yaw: float) -> NDArray[np.float64]:
    return np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])


class TabletopWorld(SensingMixin, DisturbanceMixin):
    """The Panda, ten blocks, ten lines and a three-drawer cabinet on a table, with four cameras.

    It is a :class:`voxposer.robot.Robot` and an observation source
    (:class:`voxposer.perception.perceiver.ObservationSource`); objects are found in its
    observations by perception, never by reading its bodies (those are for the benchmark's
    checks: ``object_position`` and the like). Call :meth:`reset` with a
    :class:`numpy.random.Generator` before anything else.
    """

    def __init__(self, config: WorldConfig | None = None) -> None:
        self.config = config or WorldConfig()
        self.grid = self.config.grid
        self.model = build_scene(self.config)
        self.data = mujoco.MjData(self.model)
        self.registry = ObjectRegistry(self.model)
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
        self._renderer = None
        self._obs = None
        self._obs_key: tuple[float, int, int, bool] | None = None
        self._rng = np.random.default_rng(0)
        self._gripper = 0.0
        self._unstable = False
        self._force: tuple[int, NDArray[np.float64], int] | None = None
        self.placement: Placement | None = None
        self._present: tuple[str, ...] = ()
        #: called as ``fn(world)`` after every :meth:`advance` (e.g. a video recorder)
        self.step_callbacks: list[Callable[[TabletopWorld], None]] = []

    # ------------------------------------------------------------------ reset
    def reset(self, rng: np.random.Generator, layout: SceneLayout | None = None) -> Placement:
        """Put the robot home and lay out the objects; same generator state → same world state.

        Args:
            rng: the only source of randomness (object choice and poses, IK restarts later).
            layout: which objects must be present and where; defaults to a random layout.

        Returns:
            The placement chosen (poses of the present blocks and lines, drawer openings).
        """
        layout = layout or SceneLayout()
        placement = sample_placement(layout, rng, self.config)
        (self._rng,) = rng.spawn(1)
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        d.qpos[self._arm_qpos] = HOME_Q
        half = self.config.block_size / 2
        for k, obj in enumerate(o for o in OBJECTS if o.kind == "block"):
            adr = m.joint(f"{obj.colour}_block_joint").qposadr[0]
            x, y, yaw = placement.blocks.get(str(obj.colour), (0.12 * k - 0.6, 0.0, 0.0))
            z = half if obj.colour in placement.blocks else PARKING_Z + half
            d.qpos[adr:adr + 3] = (x, y, z)
            d.qpos[adr + 3:adr + 7] = _yaw_quat(yaw)
        for k, obj in enumerate(o for o in OBJECTS if o.kind == "line"):
            mocap = m.body_mocapid[m.body(body_of(obj)).id]
            if obj.colour in placement.lines:
                x, y, yaw = placement.lines[obj.colour]
                d.mocap_pos[mocap], d.mocap_quat[mocap] = (x, y, 0.0), _yaw_quat(yaw)
            else:
                d.mocap_pos[mocap], d.mocap_quat[mocap] = (0.0, 0.05 * k, PARKING_Z - 1.0), (1, 0, 0, 0)
        cab = m.body_mocapid[m.body("cabinet").id]
        cx, cy = self.config.cabinet_position
        d.mocap_pos[cab] = (cx, cy, 0.0) if placement.cabinet else (0.0, 0.0, PARKING_Z - 3.0)
        for which, opening in placement.drawer_openings.items():
            d.qpos[m.joint(f"{which}_drawer_joint").qposadr[0]] = opening
        self._gripper = 0.0
        d.ctrl[self._arm_act] = HOME_Q
        d.ctrl[self._finger_act] = (FINGER_OPEN, -FINGER_OPEN)
        d.qpos[self._finger_qpos] = (FINGER_OPEN, -FINGER_OPEN)
        self._force = None
        self._unstable = False
        mujoco.mj_forward(m, d)
        self.controller.reset(HOME_Q)
        self.placement = placement
        present = ["table", "robot", "gripper"]
        if placement.cabinet:
            present += ["cabinet"] + [f"{w} drawer{s}" for w in DRAWERS for s in ("", " handle")]
        present += [f"{c} block" for c in placement.blocks] + [f"{c} line" for c in placement.lines]
        self._present = tuple(present)
        self._obs = None
        self.advance(25)
        if layout.ee_start is not None:
            self._move_to_start(layout.ee_start, layout.ee_start_yaw)
        return placement

    def _move_to_start(self, position: tuple[float, float, float], yaw: float = 0.0) -> None:
        """Move the end effector top-down, turned ``yaw`` [rad] about the vertical, to
        ``position`` [m] (a layout's start pose).

        Raises:
            LayoutError: the pose cannot be reached.
        """
        quat = (Rotation.from_euler("z", yaw) * Rotation.from_quat(TOP_DOWN_QUAT)).as_quat()
        try:
            result = self.move_to_pose(position, quat)
        except VoxPoserError as err:
            raise LayoutError(f"the start pose {position} is unreachable: {err}") from err
        if not result.reached:
            raise LayoutError(f"the start pose {position} was missed by "
                              f"{result.position_error * 100:.1f} cm")

    # -------------------------------------------------------------- physics
    def advance(self, nsteps: int) -> None:
        """Step the physics ``nsteps`` times with the current commands (and any active force).

        Raises:
            SimulationUnstableError: the state became NaN/inf or MuJoCo flagged bad accelerations;
                the world must be :meth:`reset` before it can step again.
        """
        if self._unstable:
            raise SimulationUnstableError("the simulation diverged earlier; call reset() first")
        m, d = self.model, self.data
        bad_before = self._bad_count()
        left = nsteps
        while left > 0:
            chunk = left
            if self._force is not None:
                body, wrench, remaining = self._force
                chunk = min(left, remaining) if remaining > 0 else left
                d.xfrc_applied[body] = wrench if remaining > 0 else 0.0
                self._force = (body, wrench, remaining - chunk) if remaining > chunk else None
                if self._force is None:
                    mujoco.mj_step(m, d, nstep=chunk)
                    d.xfrc_applied[body] = 0.0
                    left -= chunk
                    continue
            mujoco.mj_step(m, d, nstep=chunk)
            left -= chunk
        bad = self._bad_count() > bad_before
        if bad or not (np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel))):
            self._unstable = True
            raise SimulationUnstableError(
                f"simulation became unstable at t={d.time:.3f} s (NaN/inf or huge accelerations); "
                "call reset() before stepping again"
            )
        self._obs = None
        for callback in self.step_callbacks:
            callback(self)

    def _bad_count(self) -> int:
        w = self.data.warning
        return sum(int(w[k].number) for k in (mujoco.mjtWarning.mjWARN_BADQPOS,
                                              mujoco.mjtWarning.mjWARN_BADQVEL,
                                              mujoco.mjtWarning.mjWARN_BADQACC))

    def _set_gripper(self, gripper: float | None) -> bool:
        if gripper is None or (gripper >= 0.5) == (self._gripper >= 0.5):
            return False
        self._gripper = 1.0 if gripper >= 0.5 else 0.0
        opening = 0.0 if self._gripper else FINGER_OPEN
        self.data.ctrl[self._finger_act] = (opening, -opening)
        return True

    # -------------------------------------------------------------- control
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
                     speed_scale: float = 1.0, gripper: float | None = None) -> MoveResult:
        """Move the end-effector to a pose and wait until it arrives (or ``settle_time`` passes).

        Args:
            position: target [m], shape (3,).
            quat_xyzw: target orientation (x, y, z, w); None keeps the current one.
            speed_scale: multiplies the default end-effector speed.
            gripper: 1 to close or 0 to open once the pose is reached; None leaves it.

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
        for _ in range(100_000):
            wp = self.controller.next_waypoint(cmd.position, target_q, cmd.speed_scale)
            self.data.ctrl[self._arm_act] = wp.q
            self.advance(self.config.substeps)
            if wp.at_goal:
                break
        pos_err, rot_err = self._pose_error(cmd.position, target_q)
        if not np.allclose(self.controller.q_cmd, goal.q, atol=0.05) and wp.tracking_error > ctl.position_tolerance:
            log.debug("straight-line IK got stuck %.3f m short; finishing in joint space", pos_err)
            while not self.controller.joint_step(goal.q, cmd.speed_scale):
                self.data.ctrl[self._arm_act] = self.controller.q_cmd
                self.advance(self.config.substeps)
            self.data.ctrl[self._arm_act] = self.controller.q_cmd
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
