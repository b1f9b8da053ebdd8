"""A door in its frame, on a vertical hinge, with a spring-return lever handle and a latch.

Elements (in the base's frame: origin on the table under the door's centre, the door's front
face, toward the robot, in the plane x = 0):

* ``door_frame`` (the base): two posts, a lintel, feet and door stops;
* ``door`` on the hinge ``door_hinge`` (axis +z on the front face's left edge, y = −0.215 m):
  positive angles swing the door toward the robot;
* ``door_handle``, a lever on ``door_handle_joint`` (axis +x, the door's normal, 0.42 m above the
  table, 0.075 m in front of the door): positive angles press the lever down; a spring returns it.

The latch: the hinge's upper limit is ``latch_play`` while the door is latched and the full
travel while it is free. Before every physics step a latched door is freed once the lever is
pressed past ``unlatch_angle``, and a free door latches again when it is shut (``door_angle <=
latch_play``) with the lever up (a spring bolt snapping back into the strike). A latched door
therefore cannot be pulled open however hard the handle is pulled (the stop is a stiff joint
limit), and once it has swung out it stays free until it is shut again.
"""

from __future__ import annotations

from typing import ClassVar, Final

import mujoco

from voxposer.envs.articulated.articulated_object import ArticulatedObject
from voxposer.envs.articulated.config import HINGE_TRAVEL, LEVER_TRAVEL
from voxposer.envs.articulated.parts import DARK_METAL, METAL, PAINT, WOOD, add_geom, add_part_site

#: Door panel half-extents [m] (thickness, width, height) and its hinge's y in the base frame.
PANEL_HALF: Final = (0.015, 0.211, 0.35)
HINGE_Y: Final = -0.215
#: Lever pivot in the door's frame [m] (0.075 m in front of the door, 0.14 m right of centre).
PIVOT: Final = (-0.075, 0.355, 0.42)
#: The lever: a round bar pointing toward the hinge, radius and length [m]; grip centre from pivot.
LEVER_BAR: Final = (0.01, 0.12)
GRIP_OFFSET: Final = 0.075
#: The lever's spring rest angle [rad] (below its stop at 0: the lever rests preloaded).
LEVER_SPRINGREF: Final = -0.4
#: Time constant [s] of the hinge's limits (the latch's stop): stiffer than MuJoCo's 0.02 s.
LATCH_TIMECONST: Final = 0.005


class Door(ArticulatedObject):
    """The door task's object (see the module docstring)."""

    task: ClassVar[str] = "door"
    parts: ClassVar[tuple[str, ...]] = ("door frame", "door", "door handle")
    #: the lever's hub and spindle are its mount on the door: "door handle" is the bar alone
    relabel: ClassVar[dict[str, str]] = {"door_handle_hub": "door", "door_handle_spindle": "door"}
    joints: ClassVar[dict[str, str]] = {"handle_angle": "door_handle_joint",
                                        "door_angle": "door_hinge"}
    success_key: ClassVar[str] = "door_angle"
    nominal_xy: ClassVar[tuple[float, float]] = (0.185, 0.0)

    @property
    def success_threshold(self) -> float:
        """``DoorConfig.success_angle`` [rad]."""
        return self.config.door.success_angle

    def build(self, spec: mujoco.MjSpec, base: mujoco.MjsBody) -> None:
        """The frame, the door panel on its hinge and the lever (see the module docstring)."""
        self._build_frame(base)
        cfg = self.config.door
        door = base.add_body(name="door", pos=[0.0, HINGE_Y, 0.0])
        hinge = door.add_joint(name="door_hinge", type=mujoco.mjtJoint.mjJNT_HINGE,
                               axis=[0.0, 0.0, 1.0], range=[0.0, HINGE_TRAVEL])
        hinge.limited = mujoco.mjtLimited.mjLIMITED_TRUE
        hinge.damping = [cfg.hinge_damping, 0.0, 0.0]
        hinge.frictionloss = cfg.hinge_friction
        hinge.armature = 0.02
        hinge.solref_limit = [LATCH_TIMECONST, 1.0]
        tx, wy, hz = PANEL_HALF
        centre = (tx, -HINGE_Y, hz + 0.015)
        add_geom(door, "door_panel", "box", PANEL_HALF, centre, WOOD, mass=2.0)
        add_geom(door, "door_latch_bolt", "box", (0.006, 0.012, 0.008),
                 (tx, centre[1] + wy + 0.008, PIVOT[2]), METAL, collide=False)
        for k, z in enumerate((0.12, 0.56)):
            add_geom(door, f"door_knuckle_{k}", "cylinder", (0.008, 0.03), (0.0, 0.0, z),
                     METAL, collide=False)
        add_geom(door, "door_rose", "cylinder", (0.028,), collide=False, rgba=METAL,
                 fromto=(-0.008, PIVOT[1], PIVOT[2], 0.0, PIVOT[1], PIVOT[2]))
        add_part_site(door, centre)
        self._build_lever(door)

    @staticmethod
    def _build_frame(base: mujoco.MjsBody) -> None:
        post_y = -HINGE_Y + 0.025
        for k, side in enumerate((-1.0, 1.0)):
            add_geom(base, f"door_frame_post_{k}", "box", (0.025, 0.02, 0.36),
                     (0.015, side * post_y, 0.36), PAINT)
            add_geom(base, f"door_frame_foot_{k}", "box", (0.10, 0.03, 0.01),
                     (0.015, side * post_y, 0.01), PAINT)
            add_geom(base, f"door_frame_stop_{k}", "box", (0.005, 0.01, 0.33),
                     (0.035, side * (-HINGE_Y - 0.002), 0.36), PAINT, collide=False)
        add_geom(base, "door_frame_lintel", "box", (0.025, post_y + 0.02, 0.02),
                 (0.015, 0.0, 0.74), PAINT)
        add_part_site(base, (0.015, 0.0, 0.36))

    def _build_lever(self, door: mujoco.MjsBody) -> None:
        lever = door.add_body(name="door_handle", pos=list(PIVOT))
        joint = lever.add_joint(name="door_handle_joint", type=mujoco.mjtJoint.mjJNT_HINGE,
                                axis=[1.0, 0.0, 0.0], range=[0.0, LEVER_TRAVEL])
        joint.limited = mujoco.mjtLimited.mjLIMITED_TRUE
        joint.stiffness = [self.config.door.lever_stiffness, 0.0, 0.0]
        joint.springref = LEVER_SPRINGREF
        joint.damping = [0.01, 0.0, 0.0]
        joint.armature = 0.002
        radius, length = LEVER_BAR
        add_geom(lever, "door_handle_hub", "cylinder", (0.016,), rgba=DARK_METAL, mass=0.04,
                 fromto=(-0.014, 0.0, 0.0, 0.014, 0.0, 0.0))
        add_geom(lever, "door_handle_spindle", "cylinder", (0.009,), rgba=DARK_METAL, mass=0.02,
                 fromto=(0.014, 0.0, 0.0, -PIVOT[0] - 0.008, 0.0, 0.0))
        add_geom(lever, "door_handle_lever", "capsule", (radius,), rgba=DARK_METAL, mass=0.1,
                 fromto=(0.0, 0.0, 0.0, 0.0, -length, 0.0), friction=1.5)
        add_part_site(lever, (0.0, -GRIP_OFFSET, 0.0))

    def before_step(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """The latch: a latched door is freed once the lever is pressed past ``unlatch_angle``;
        a free door latches when it is shut (within ``latch_play``) with the lever up."""
        cfg = self.config.door
        lever_up = data.qpos[self._qadr["handle_angle"]] < cfg.unlatch_angle
        if self.latched(model):
            if not lever_up:
                model.jnt_range[self._jnt["door_angle"], 1] = HINGE_TRAVEL
        elif lever_up and data.qpos[self._qadr["door_angle"]] <= cfg.latch_play:
            model.jnt_range[self._jnt["door_angle"], 1] = cfg.latch_play

    def reset_mechanism(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        """Latched exactly when the door is shut and the lever up."""
        model.jnt_range[self._jnt["door_angle"], 1] = HINGE_TRAVEL
        self.before_step(model, data)

    def latched(self, model: mujoco.MjModel) -> bool:
        """Whether the latch holds the door now (its hinge's upper limit is ``latch_play``)."""
        return bool(model.jnt_range[self._jnt["door_angle"], 1] < HINGE_TRAVEL)


__all__ = ["Door"]
