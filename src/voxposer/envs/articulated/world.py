"""``ArticulatedWorld``: the Panda and one articulated object (door, window, fridge) on a table.

The scenes of the paper's online dynamics learning (Sec. 3.4, 4.3, Table 3). The world is a
:class:`voxposer.robot.Robot` (the tabletop's pose controller, :mod:`voxposer.envs.arm`) and an
observation source like :class:`~voxposer.envs.world.TabletopWorld`: four RGB-D views with a
ground-truth label channel whose names are the object's parts (then "table", "robot",
"gripper"). :meth:`articulation_state`, :meth:`part_position`, :meth:`joint_axis` and
:meth:`success` read the simulator's ground truth: they are for checks, tests and reference
programs, not for a policy.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from voxposer.envs.arm import ArmControlMixin
from voxposer.envs.articulated.articulated_object import JointAxis
from voxposer.envs.articulated.config import ArticulatedConfig
from voxposer.envs.articulated.scene import build_scene, geom_labels, label_names, make_object
from voxposer.envs.cameras import CameraRenderer
from voxposer.envs.ik import HOME_Q
from voxposer.envs.robot_model import FINGER_OPEN
from voxposer.envs.stepping import SteppedPhysicsMixin
from voxposer.envs.views import CameraViewsMixin
from voxposer.perception.observation import Observation


@dataclass(frozen=True)
class ArticulatedPlacement:
    """What a reset chose.

    Attributes:
        task: "door", "window" or "fridge".
        object_xy: the object's base position on the table (x, y) [m].
        object_yaw: the object's yaw about the vertical [rad].
        arm_q: the arm's start joint angles [rad], 7 values.
    """

    task: str
    object_xy: tuple[float, float]
    object_yaw: float
    arm_q: tuple[float, ...]


class ArticulatedWorld(CameraViewsMixin, SteppedPhysicsMixin, ArmControlMixin):
    """The Panda and the object of ``task`` ("door", "window", "fridge") with four cameras.

    Call :meth:`reset` with a :class:`numpy.random.Generator` before anything else.

    Args:
        task: the articulated task; unknown names raise ``ConfigError`` listing the known ones.
        config: scene, randomisation, mechanisms and thresholds (defaults: ``ArticulatedConfig()``).
    """

    config: ArticulatedConfig

    def __init__(self, task: str, config: ArticulatedConfig | None = None) -> None:
        self.config = config or ArticulatedConfig()
        self.object = make_object(task, self.config)
        self.task = task
        self.grid = self.config.grid
        self.model = build_scene(self.config, self.object)
        self.data = mujoco.MjData(self.model)
        self.object.bind(self.model)
        self._bind_arm()
        #: names of the segmentation labels: the object's parts, "table", "robot", "gripper"
        self.label_names = label_names(self.object)
        self._geom_labels = geom_labels(self.model, self.object)
        self._mocap = int(self.model.body_mocapid[self.model.body(self.object.base_body).id])
        self._renderer: CameraRenderer | None = None
        self._obs: Observation | None = None
        self._obs_key: tuple[float, int, int, bool, bool] | None = None
        self._rng = np.random.default_rng(0)
        self._gripper = 0.0
        self._unstable = False
        self.placement: ArticulatedPlacement | None = None
        #: called as ``fn(world)`` after every :meth:`advance` (e.g. a video recorder)
        self.step_callbacks: list[Callable[[ArticulatedWorld], None]] = []
        mujoco.mj_forward(self.model, self.data)

    # ------------------------------------------------------------------ reset
    def reset(self, rng: np.random.Generator) -> ArticulatedPlacement:
        """Shut the object, put the robot near home and place the object (ranges:
        :class:`ArticulatedConfig`); same generator state → same world state.

        Args:
            rng: the only source of randomness (arm start, object pose, IK restarts later).
        """
        cfg, m, d = self.config, self.model, self.data
        noise = rng.uniform(-cfg.joint_noise, cfg.joint_noise, 7)
        q0 = np.clip(np.add(HOME_Q, noise), self.ik.lower, self.ik.upper)
        dx, dy = rng.uniform(-cfg.position_noise, cfg.position_noise, 2)
        yaw = float(rng.uniform(-cfg.yaw_noise, cfg.yaw_noise))
        (self._rng,) = rng.spawn(1)
        mujoco.mj_resetData(m, d)
        d.qpos[self._arm_qpos] = q0
        d.ctrl[self._arm_act] = q0
        d.qpos[self._finger_qpos] = (FINGER_OPEN, -FINGER_OPEN)
        d.ctrl[self._finger_act] = (FINGER_OPEN, -FINGER_OPEN)
        x, y = self.object.nominal_xy[0] + dx, self.object.nominal_xy[1] + dy
        d.mocap_pos[self._mocap] = (x, y, 0.0)
        d.mocap_quat[self._mocap] = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
        self._gripper = 0.0
        self._unstable = False
        self.object.reset_mechanism(m, d)
        mujoco.mj_forward(m, d)
        self.controller.reset(q0)
        self.placement = ArticulatedPlacement(self.task, (float(x), float(y)), yaw,
                                              tuple(float(q) for q in q0))
        self._obs = None
        self.advance(25)
        return self.placement

    # -------------------------------------------------------------- physics
    def _integrate(self, nsteps: int) -> None:
        """Step the physics ``nsteps`` times with the current commands, running the object's
        mechanism (latch, seal) before each step (:meth:`advance` checks the result)."""
        m, d = self.model, self.data
        for _ in range(nsteps):
            self.object.before_step(m, d)
            mujoco.mj_step(m, d)

    # ---------------------------------------------------------- observation
    @property
    def object_names(self) -> tuple[str, ...]:
        """Names of the scene's labelled objects (:attr:`label_names`)."""
        return self.label_names

    def _geom_label_ids(self) -> NDArray[np.int32]:
        return self._geom_labels

    def _label_names(self) -> tuple[str, ...]:
        return self.label_names

    # --------------------------------------------------------- ground truth
    def articulation_state(self) -> dict[str, float]:
        """Ground-truth joint values, for checks and tests only: ``{"handle_angle": rad,
        "door_angle": rad}`` (door), ``{"window_offset": m}`` (window), ``{"door_angle": rad}``
        (fridge)."""
        return self.object.state(self.data)

    def set_articulation_state(self, values: Mapping[str, float]) -> None:
        """Set joint values (keys of :meth:`articulation_state`) directly, at rest; for tests.

        Raises:
            LayoutError: an unknown key or a value outside the joint's range.
        """
        self.object.set_state(self.model, self.data, values)
        mujoco.mj_forward(self.model, self.data)
        self._obs = None

    def part_position(self, name: str) -> NDArray[np.float64]:
        """Ground-truth world position [m], shape (3,), of a part ("door handle": the lever's
        grip centre; a panel: its centre; the base: the middle of its opening or body).

        Raises:
            UnknownObjectError: listing the object's parts.
        """
        return self.object.part_position(self.data, name)

    def joint_axis(self, key: str) -> JointAxis:
        """Ground-truth world axis of the joint behind an :meth:`articulation_state` key."""
        return self.object.axis(self.data, key)

    def success(self) -> tuple[bool, str]:
        """Whether the object is open enough (``door_angle >= DoorConfig.success_angle``,
        ``window_offset >= WindowConfig.success_offset``, the fridge's ``door_angle >=
        FridgeConfig.success_angle``), and a reason stating the measured value and threshold."""
        return self.object.success(self.data)


__all__ = ["ArticulatedPlacement", "ArticulatedWorld"]
