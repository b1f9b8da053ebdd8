"""The tabletop's layout, described once (paper App. A.5): table, robot base, workspace, object
sizes and the cabinet with its drawers.

A base module: the simulator builds its MuJoCo scene from these numbers (its ``WorldConfig``
defaults are these), the programs' box test scene (:func:`voxposer.lmp.scene.make_tabletop_scene`)
lays out the same cabinet, and the table places (:mod:`voxposer.places`) are fractions of the
same table. World frame: metres, z up, front = +x, right = +y; the table top is z = 0.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

from voxposer.catalog import DRAWERS

#: Table top extent in x, y [m].
TABLE_MIN: Final = (-0.70, -0.50)
TABLE_MAX: Final = (0.30, 0.50)
#: The robot's base [m]: at the back of the table, facing +x.
ROBOT_BASE: Final = (-0.60, 0.0, 0.0)
#: The voxel workspace box [m] and its voxels per axis (about 1 cm voxels).
WORKSPACE_MIN: Final = (-0.70, -0.50, -0.02)
WORKSPACE_MAX: Final = (0.30, 0.50, 0.98)
GRID_SHAPE: Final = (100, 100, 100)
#: Edge of the cube blocks [m]; length and width of the flat lines [m].
BLOCK_SIZE: Final = 0.05
LINE_LENGTH: Final = 0.20
LINE_WIDTH: Final = 0.012
#: Centre (x, y) of the cabinet on the table [m]; its drawers open toward −y.
CABINET_POSITION: Final = (-0.05, 0.37)
#: Cabinet outer size along x, y, z [m]; wall thickness [m]; how far a drawer slides out [m].
CABINET_SIZE: Final = (0.32, 0.26, 0.36)
CABINET_WALL: Final = 0.012
DRAWER_TRAVEL: Final = 0.20
#: A drawer handle's bar: half-extents [m]; how far its centre stands in front of the cabinet [m].
HANDLE_HALF: Final = (0.07, 0.008, 0.008)
HANDLE_STANDOFF: Final = 0.03


@dataclass(frozen=True)
class DrawerSlot:
    """Where one drawer sits in the cabinet, in the cabinet's frame (origin at its footprint's
    centre on the table).

    Attributes:
        name: "top", "middle" or "bottom".
        centre_z: height of the drawer's centre [m].
        half_height: half of the drawer front's height [m].
    """

    name: str
    centre_z: float
    half_height: float


def drawer_slots() -> tuple[DrawerSlot, ...]:
    """The three drawers, top to bottom: each fills one third of the cabinet's inner height."""
    sz = CABINET_SIZE[2] / 2
    slot = (2 * sz - 2 * CABINET_WALL) / len(DRAWERS)
    out = []
    for k, which in enumerate(DRAWERS):
        bottom = 2 * sz - CABINET_WALL - (k + 1) * slot
        out.append(DrawerSlot(which, bottom + slot / 2, slot / 2 - 0.006))
    return tuple(out)


__all__ = ["BLOCK_SIZE", "CABINET_POSITION", "CABINET_SIZE", "CABINET_WALL", "DRAWER_TRAVEL",
           "GRID_SHAPE", "HANDLE_HALF", "HANDLE_STANDOFF", "LINE_LENGTH", "LINE_WIDTH",
           "ROBOT_BASE", "TABLE_MAX", "TABLE_MIN", "WORKSPACE_MAX", "WORKSPACE_MIN",
           "DrawerSlot", "drawer_slots"]
