"""The one abstract base of the articulated objects: parts, joints, mechanism and success check.

An :class:`ArticulatedObject` builds itself under a base body (a mocap body standing on the
table, placed by the world at reset), names its parts (segmentation labels; each part is the
body of the same name with underscores, with a reference site ``<body>_site``), exposes its
joints as named ground-truth values (``"door_angle"`` [rad], ``"window_offset"`` [m]) and may
run a mechanism (a latch, a magnetic seal) before every physics step.
"""

from __future__ import annotations

import abc
import math
from collections.abc import Mapping
from typing import ClassVar, NamedTuple

import mujoco
import numpy as np
from numpy.typing import NDArray

from voxposer.envs.articulated.config import ArticulatedConfig
from voxposer.errors import LayoutError, UnknownObjectError


def body_name(part: str) -> str:
    """The MuJoCo body of a part ("door handle" → ``door_handle``)."""
    return part.replace(" ", "_")


class JointAxis(NamedTuple):
    """Where a joint is, in world coordinates.

    Attributes:
        anchor: a point on the joint's axis [m], shape (3,).
        direction: the unit axis, shape (3,): positive rotation (right-hand rule) or sliding
            along it increases the joint's value.
    """

    anchor: NDArray[np.float64]
    direction: NDArray[np.float64]


class ArticulatedObject(abc.ABC):
    """An object with joints, standing on the table with its handle toward the robot.

    Class attributes of each subclass:
        task: the task name ("door").
        parts: segmentation label names of its parts, the base part first.
        joints: ground-truth key → joint name; keys ending in ``_angle`` are [rad], the others [m].
        success_key: the key compared with :attr:`success_threshold`.
        nominal_xy: where the base stands on the table before randomisation (x, y) [m].
    """

    task: ClassVar[str]
    parts: ClassVar[tuple[str, ...]]
    joints: ClassVar[dict[str, str]]
    success_key: ClassVar[str]
    nominal_xy: ClassVar[tuple[float, float]]
    #: geoms labelled as another part than their body's (a handle's mount seen as the door)
    relabel: ClassVar[dict[str, str]] = {}

    def __init__(self, config: ArticulatedConfig) -> None:
        self.config = config
        self._jnt: dict[str, int] = {}
        self._qadr: dict[str, int] = {}
        self._sites: dict[str, int] = {}
        self._range: dict[str, tuple[float, float]] = {}

    @property
    def base_body(self) -> str:
        """The mocap body the object is built under (its base part's body)."""
        return body_name(self.parts[0])

    @property
    @abc.abstractmethod
    def success_threshold(self) -> float:
        """The value of :attr:`success_key` from which the task counts as done [rad] or [m]."""

    @abc.abstractmethod
    def build(self, spec: mujoco.MjSpec, base: mujoco.MjsBody) -> None:
        """Add every body, joint, geom and part site under ``base`` (at table height, local x
        pointing away from the robot), and any actuator of a mechanism to ``spec``."""

    def bind(self, model: mujoco.MjModel) -> None:
        """Look up the joints and sites in the compiled model (call once after compiling)."""
        for key, joint in self.joints.items():
            self._jnt[key] = int(model.joint(joint).id)
            self._qadr[key] = int(model.jnt_qposadr[self._jnt[key]])
            lo, hi = model.jnt_range[self._jnt[key]]
            self._range[key] = (float(lo), float(hi))  # as compiled (a latch narrows it later)
        for part in self.parts:
            self._sites[part] = int(model.site(f"{body_name(part)}_site").id)

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Run the mechanism (latch, seal) for the coming physics step; none by default."""
        return None

    def reset_mechanism(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Put the mechanism in the state the joints imply (after a reset or a direct set of
        the joints); by default the same as :meth:`before_step`."""
        self.before_step(model, data)

    def state(self, data: mujoco.MjData) -> dict[str, float]:
        """Ground-truth joint values, key → [rad] or [m]."""
        return {key: float(data.qpos[adr]) for key, adr in self._qadr.items()}

    def set_state(self, model: mujoco.MjModel, data: mujoco.MjData,
                  values: Mapping[str, float]) -> None:
        """Set joint values (key → [rad] or [m]) directly, with zero velocity.

        Raises:
            LayoutError: an unknown key, or a value outside the joint's range.
        """
        for key, value in values.items():
            if key not in self._qadr:
                raise LayoutError(f"unknown articulation key {key!r}; keys are: "
                                  f"{', '.join(self._qadr)}")
            lo, hi = self._range[key]
            if not (math.isfinite(value) and lo - 1e-9 <= value <= hi + 1e-9):
                raise LayoutError(f"{key} must be in [{lo:.4g}, {hi:.4g}]; got {value!r}")
            data.qpos[self._qadr[key]] = value
            data.qvel[model.jnt_dofadr[self._jnt[key]]] = 0.0
        self.reset_mechanism(model, data)

    def part_position(self, data: mujoco.MjData, part: str) -> NDArray[np.float64]:
        """World position [m], shape (3,), of a part's reference point (a handle's grip centre,
        a panel's centre, the middle of the base's opening or body).

        Raises:
            UnknownObjectError: listing the object's parts.
        """
        if part not in self._sites:
            raise UnknownObjectError(part, self.parts)
        return np.asarray(data.site_xpos[self._sites[part]], dtype=np.float64).copy()

    def axis(self, data: mujoco.MjData, key: str) -> JointAxis:
        """The world axis of the joint behind ``key`` (needs a current ``mj_forward``).

        Raises:
            LayoutError: an unknown key.
        """
        if key not in self._jnt:
            raise LayoutError(f"unknown articulation key {key!r}; keys are: {', '.join(self._jnt)}")
        jid = self._jnt[key]
        return JointAxis(np.asarray(data.xanchor[jid], dtype=np.float64).copy(),
                         np.asarray(data.xaxis[jid], dtype=np.float64).copy())

    def success(self, data: mujoco.MjData) -> tuple[bool, str]:
        """Whether :attr:`success_key` reached :attr:`success_threshold`, and why (with the
        measured value and the threshold)."""
        value = self.state(data)[self.success_key]
        threshold = self.success_threshold
        ok = value >= threshold
        return ok, (f"{self.success_key} {describe(self.success_key, value)} "
                    f"{'>=' if ok else '<'} threshold {describe(self.success_key, threshold)}")


def describe(key: str, value: float) -> str:
    """A ground-truth value in readable units: angles in degrees, offsets in centimetres."""
    if key.endswith("_angle"):
        return f"{math.degrees(value):.1f}°"
    return f"{value * 100:.1f} cm"


__all__ = ["ArticulatedObject", "JointAxis", "body_name", "describe"]
