"""A fridge whose door, on a vertical hinge, is held shut by a magnetic seal.

Elements (in the base's frame: origin on the table under the middle of the fridge's open
front, which is the plane x = 0; the cabinet extends to x = 0.32 m, away from the robot):

* ``fridge`` (the base): the cabinet's walls and a shelf;
* ``fridge_door`` on ``fridge_hinge`` (axis +z on the front's left edge, y = −0.20 m): positive
  angles swing the door toward the robot;
* ``fridge_handle``, a bar across the door, 0.075 m in front of it, near its free edge;
* ``fridge_seal``, a torque actuator on the hinge driven by the seal, not by the robot.

The seal: before every physics step ``fridge_seal`` pulls the door shut with the torque
``seal_force * r - hinge_friction`` (r: the handle's distance from the hinge axis, so that the
pull that opens the door, normal to it at the handle, is ``seal_force``) while the door is within
``seal_range / 5`` of shut, fading linearly to zero at ``seal_range`` (a magnet's short reach).
"""

from __future__ import annotations

from typing import ClassVar, Final

import mujoco

from voxposer.envs.articulated.articulated_object import ArticulatedObject
from voxposer.envs.articulated.config import HINGE_TRAVEL
from voxposer.envs.articulated.parts import DARK_METAL, METAL, PAINT, add_geom, add_part_site

#: Cabinet outer size [m] along x (depth), y (width), z (height) and its wall thickness [m].
CABINET: Final = (0.32, 0.40, 0.66)
WALL: Final = 0.01
#: Door thickness [m]; the handle bar's centre in the door's frame [m], its radius and
#: half-length [m] (the bar runs across the door, along its width).
DOOR_T: Final = 0.03
HANDLE_POS: Final = (-0.105, 0.30, 0.42)
HANDLE_BAR: Final = (0.012, 0.07)
#: Fraction of ``seal_range`` over which the seal pulls with its full torque.
FULL_SEAL: Final = 0.2


class Fridge(ArticulatedObject):
    """The fridge task's object (see the module docstring)."""

    task: ClassVar[str] = "fridge"
    parts: ClassVar[tuple[str, ...]] = ("fridge", "fridge door", "fridge handle")
    joints: ClassVar[dict[str, str]] = {"door_angle": "fridge_hinge"}
    success_key: ClassVar[str] = "door_angle"
    nominal_xy: ClassVar[tuple[float, float]] = (0.16, 0.0)

    @property
    def success_threshold(self) -> float:
        """``FridgeConfig.success_angle`` [rad]."""
        return self.config.fridge.success_angle

    @property
    def seal_torque(self) -> float:
        """The seal's full closing torque [N m]."""
        cfg = self.config.fridge
        return max(0.0, cfg.seal_force * HANDLE_POS[1] - cfg.hinge_friction)

    def build(self, spec: mujoco.MjSpec, base: mujoco.MjsBody) -> None:
        """The cabinet, the door on its hinge with the handle, and the seal's actuator."""
        self._build_cabinet(base)
        cfg = self.config.fridge
        _, wy, hz = (c / 2 for c in CABINET)
        door = base.add_body(name="fridge_door", pos=[0.0, -wy, 0.0])
        hinge = door.add_joint(name="fridge_hinge", type=mujoco.mjtJoint.mjJNT_HINGE,
                               axis=[0.0, 0.0, 1.0], range=[0.0, HINGE_TRAVEL])
        hinge.limited = mujoco.mjtLimited.mjLIMITED_TRUE
        hinge.damping = [cfg.hinge_damping, 0.0, 0.0]
        hinge.frictionloss = cfg.hinge_friction
        hinge.armature = 0.02
        centre = (-DOOR_T / 2, wy, hz)
        add_geom(door, "fridge_door_panel", "box", (DOOR_T / 2, wy, hz), centre, PAINT, mass=2.5)
        add_geom(door, "fridge_door_gasket", "box", (0.003, wy - 0.01, hz - 0.01),
                 (0.003, wy, hz), (0.3, 0.3, 0.3, 1.0), collide=False)
        add_part_site(door, centre)
        handle = door.add_body(name="fridge_handle", pos=list(HANDLE_POS))
        radius, half = HANDLE_BAR
        add_geom(handle, "fridge_handle_bar", "capsule", (radius,), rgba=METAL, mass=0.1,
                 fromto=(0.0, -half, 0.0, 0.0, half, 0.0), friction=1.5)
        standoff = -HANDLE_POS[0] - DOOR_T
        for k, side in enumerate((-1.0, 1.0)):
            add_geom(handle, f"fridge_handle_post_{k}", "box", (standoff / 2, 0.008, 0.008),
                     (standoff / 2, side * (half - 0.008), 0.0), DARK_METAL, mass=0.02)
        add_part_site(handle)
        seal = spec.add_actuator(name="fridge_seal", target="fridge_hinge")
        seal.trntype = mujoco.mjtTrn.mjTRN_JOINT
        seal.set_to_motor()
        seal.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
        seal.ctrlrange = [-self.seal_torque, 0.0]

    @staticmethod
    def _build_cabinet(base: mujoco.MjsBody) -> None:
        dx, wy, hz = (c / 2 for c in CABINET)
        w = WALL / 2
        add_geom(base, "fridge_back", "box", (w, wy, hz), (2 * dx - w, 0.0, hz), PAINT)
        add_geom(base, "fridge_top", "box", (dx, wy, w), (dx, 0.0, 2 * hz - w), PAINT)
        add_geom(base, "fridge_bottom", "box", (dx, wy, w), (dx, 0.0, w), PAINT)
        for k, side in enumerate((-1.0, 1.0)):
            add_geom(base, f"fridge_side_{k}", "box", (dx, w, hz), (dx, side * (wy - w), hz), PAINT)
        add_geom(base, "fridge_shelf", "box", (dx - WALL, wy - WALL, 0.004), (dx, 0.0, hz),
                 (0.85, 0.90, 0.95, 1.0))
        add_part_site(base, (dx, 0.0, hz))

    def bind(self, model: mujoco.MjModel) -> None:
        """Joints and sites, and the seal's actuator."""
        super().bind(model)
        self._seal = int(model.actuator("fridge_seal").id)

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """The seal: a closing torque that fades from full at ``seal_range / 5`` to none at
        ``seal_range``."""
        reach = self.config.fridge.seal_range
        angle = float(data.qpos[self._qadr["door_angle"]])
        strength = min(1.0, max(0.0, (reach - angle) / (reach * (1.0 - FULL_SEAL))))
        data.ctrl[self._seal] = -self.seal_torque * strength


__all__ = ["Fridge"]
