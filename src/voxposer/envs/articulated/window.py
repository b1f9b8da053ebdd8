"""A sliding window: a sash that slides sideways (to the left, −y) in its frame, with a knob.

Elements (in the base's frame: origin on the table under the window's centre; the robot is on
the −x side):

* ``window_frame`` (the base): a low wall, sill, head and jambs around an opening 0.66 m wide
  (y) and 0.36 m tall (z from 0.25 to 0.61 m), and a fixed pane in the back track (left half);
* ``window``, the sash in the front track on ``window_slide`` (axis −y, 0 = shut over the right
  half, up to 0.28 m open), with dry friction and damping so that a light touch does not move it;
* ``window_handle``, a knob sticking out of the sash's front near its right stile (its
  reference point 0.045 m out, where it is gripped).
"""

from __future__ import annotations

from typing import ClassVar, Final

import mujoco

from voxposer.envs.articulated.articulated_object import ArticulatedObject
from voxposer.envs.articulated.config import SASH_TRAVEL
from voxposer.envs.articulated.parts import (
    DARK_METAL,
    GLASS,
    PAINT,
    add_geom,
    add_part_site,
)

#: The opening's half-width [m] and its bottom and top heights [m].
OPENING_HALF_W: Final = 0.33
OPENING_Z: Final = (0.25, 0.61)
#: The sash's half-extents [m] (thickness, width, height) and its centre in the base frame [m].
SASH_HALF: Final = (0.012, 0.165, 0.175)
SASH_CENTRE: Final = (-0.02, 0.17, 0.43)
#: The handle, a knob sticking out of the sash toward the robot: its root in the sash's frame
#: [m], its radius and length [m].
HANDLE_POS: Final = (-0.012, 0.11, 0.0)
HANDLE_KNOB: Final = (0.012, 0.065)


class Window(ArticulatedObject):
    """The window task's object (see the module docstring)."""

    task: ClassVar[str] = "window"
    parts: ClassVar[tuple[str, ...]] = ("window frame", "window", "window handle")
    joints: ClassVar[dict[str, str]] = {"window_offset": "window_slide"}
    success_key: ClassVar[str] = "window_offset"
    nominal_xy: ClassVar[tuple[float, float]] = (0.12, 0.0)

    @property
    def success_threshold(self) -> float:
        """``WindowConfig.success_offset`` [m]."""
        return self.config.window.success_offset

    def build(self, spec: mujoco.MjSpec, base: mujoco.MjsBody) -> None:
        """The frame, the fixed pane, the sliding sash and its handle."""
        self._build_frame(base)
        cfg = self.config.window
        sash = base.add_body(name="window", pos=list(SASH_CENTRE))
        slide = sash.add_joint(name="window_slide", type=mujoco.mjtJoint.mjJNT_SLIDE,
                               axis=[0.0, -1.0, 0.0], range=[0.0, SASH_TRAVEL])
        slide.limited = mujoco.mjtLimited.mjLIMITED_TRUE
        slide.damping = [cfg.damping, 0.0, 0.0]
        slide.frictionloss = cfg.frictionloss
        slide.armature = 0.1
        tx, wy, hz = SASH_HALF
        for k, side in enumerate((-1.0, 1.0)):
            add_geom(sash, f"window_stile_{k}", "box", (tx, 0.015, hz),
                     (0.0, side * (wy - 0.015), 0.0), PAINT, mass=0.4)
            add_geom(sash, f"window_rail_{k}", "box", (tx, wy - 0.03, 0.015),
                     (0.0, 0.0, side * (hz - 0.015)), PAINT, mass=0.3)
        add_geom(sash, "window_glass", "box", (0.004, wy - 0.03, hz - 0.03), rgba=GLASS, mass=0.2)
        add_part_site(sash)
        handle = sash.add_body(name="window_handle", pos=list(HANDLE_POS))
        radius, length = HANDLE_KNOB
        add_geom(handle, "window_handle_knob", "cylinder", (radius,), rgba=DARK_METAL, mass=0.05,
                 fromto=(0.0, 0.0, 0.0, -length, 0.0, 0.0), friction=1.5)
        add_geom(handle, "window_handle_cap", "cylinder", (radius + 0.008,), rgba=DARK_METAL,
                 mass=0.02, fromto=(-length, 0.0, 0.0, -length - 0.008, 0.0, 0.0))
        add_part_site(handle, (-0.045, 0.0, 0.0))

    @staticmethod
    def _build_frame(base: mujoco.MjsBody) -> None:
        lo, hi = OPENING_Z
        outer = OPENING_HALF_W + 0.04
        add_geom(base, "window_frame_wall", "box", (0.03, outer, (lo - 0.02) / 2),
                 (0.0, 0.0, (lo - 0.02) / 2), PAINT)
        add_geom(base, "window_frame_sill", "box", (0.045, outer, 0.01), (0.0, 0.0, lo - 0.01),
                 PAINT)
        add_geom(base, "window_frame_head", "box", (0.045, outer, 0.02), (0.0, 0.0, hi + 0.02),
                 PAINT)
        for k, side in enumerate((-1.0, 1.0)):
            add_geom(base, f"window_frame_jamb_{k}", "box", (0.045, 0.02, (hi - lo) / 2),
                     (0.0, side * (OPENING_HALF_W + 0.02), (lo + hi) / 2), PAINT)
        pane_w = OPENING_HALF_W / 2
        centre = (0.02, -pane_w, (lo + hi) / 2)
        add_geom(base, "window_frame_pane", "box", (0.004, pane_w - 0.01, (hi - lo) / 2 - 0.01),
                 centre, GLASS)
        add_geom(base, "window_frame_mullion", "box", (0.01, 0.012, (hi - lo) / 2),
                 (0.02, -0.012, (lo + hi) / 2), PAINT)
        add_part_site(base, (0.0, 0.0, (lo + hi) / 2))


__all__ = ["Window"]
