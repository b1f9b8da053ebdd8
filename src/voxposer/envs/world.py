"""``TabletopWorld``: the simulated tabletop of the paper (App. A.5) behind one small facade.

Physics, control and cameras of the MuJoCo scene built by
:mod:`voxposer.envs.scene`. Public quaternions are scalar-last (x, y, z, w); the end-effector's
approach axis is its local +z (a top-down grasp points along world −z, :data:`TOP_DOWN_QUAT`).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import mujoco
import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from voxposer.catalog import DRAWERS, OBJECTS
from voxposer.envs.arm import ArmControlMixin
from voxposer.envs.config import WorldConfig
from voxposer.envs.disturbances import DisturbanceMixin
from voxposer.envs.ik import HOME_Q
from voxposer.envs.layout import Placement, SceneLayout, sample_placement
from voxposer.envs.registry import ObjectRegistry, body_of
from voxposer.envs.robot_model import FINGER_OPEN
from voxposer.envs.scene import PARKING_Z, build_scene
from voxposer.envs.sensing import SensingMixin
from voxposer.envs.stepping import SteppedPhysicsMixin
from voxposer.errors import LayoutError, VoxPoserError
from voxposer.geometry.frames import TOP_DOWN_QUAT as _TOP_DOWN
from voxposer.robot import MoveResult, StepResult

__all__ = ["TOP_DOWN_QUAT", "MoveResult", "StepResult", "TabletopWorld"]

#: Top-down end-effector orientation (x, y, z, w): approach axis along world −z, fingers along y.
TOP_DOWN_QUAT: NDArray[np.float64] = np.array(_TOP_DOWN)
TOP_DOWN_QUAT.flags.writeable = False


def _yaw_quat(yaw: float) -> NDArray[np.float64]:
    return np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])


class TabletopWorld(SensingMixin, SteppedPhysicsMixin, DisturbanceMixin, ArmControlMixin):
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
        self._bind_arm()
        self._renderer = None
        self._obs = None
        self._obs_key: tuple[float, int, int, bool, bool] | None = None
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
        # blocks and lines by name, not as the layout placed them: the order must not tell
        # which of them a task named (the layout places those first)
        present += [f"{c} block" for c in sorted(placement.blocks)]
        present += [f"{c} line" for c in sorted(placement.lines)]
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
    def _integrate(self, nsteps: int) -> None:
        """Step the physics ``nsteps`` times with the current commands and any active force
        (:meth:`advance` checks the result)."""
        m, d = self.model, self.data
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
