"""The cabinet, its drawers and their handles, fitted to depth in a known fixture's box.

The cabinet is a fixture whose place and size come from the table's description
(:mod:`voxposer.tabletop`): whether it stands there is measured (enough points inside its box),
and how far each drawer is open is measured from depth: the drawer's front is the plane of the
points facing out of the cabinet (−y) in that drawer's height band, away from the handle; its
offset from the cabinet's front is the opening. Around that plane the drawer's points are
those of its band between the handle's standoff and the cabinet's front (an open drawer's
walls and floor stick out), the handle those standing in front of the drawer's face.
"""

from __future__ import annotations

from typing import Final, NamedTuple

import numpy as np
from numpy.typing import NDArray

from voxposer.tabletop import (
    CABINET_POSITION,
    CABINET_SIZE,
    CABINET_WALL,
    DRAWER_TRAVEL,
    HANDLE_HALF,
    HANDLE_STANDOFF,
    drawer_slots,
)

#: Fewest points inside the cabinet's box for it to count as present.
MIN_CABINET_POINTS: Final = 150
#: Only points higher than this [m] count toward the cabinet's presence and body: lower ones
#: may be the table's (a consumer RGB-D camera's table points reach 2 cm:
#: :data:`voxposer.perception.pixel_labels.TABLE_TOP_M`); at 3 mm, the noisy table inside an
#: absent cabinet's box made a cabinet, an obstacle at the front of the table.
ABOVE_TABLE_M: Final = 0.02
#: Fewest front-facing points for a drawer's front plane to be measured.
MIN_FRONT_POINTS: Final = 15
#: Margin [m] around the cabinet's box and a drawer's band that still counts as inside.
MARGIN_M: Final = 0.004
#: A drawer's length from its front face to its rear [m].
DRAWER_LENGTH_M: Final = CABINET_SIZE[1] - 2 * CABINET_WALL
#: A point faces out of the cabinet when its normal's −y component exceeds this.
FACING: Final = 0.8


class CabinetFit(NamedTuple):
    """What was measured of the cabinet.

    Attributes:
        present: enough points in the cabinet's box.
        openings: drawer ("top", "middle", "bottom") → measured opening [m] (0 closed, at most
            :data:`DRAWER_TRAVEL`); drawers whose front no camera sees are absent.
        parts: part name ("cabinet", "top drawer", "top drawer handle", …) → indices of its
            points among the candidates given.
    """

    present: bool
    openings: dict[str, float]
    parts: dict[str, NDArray[np.int64]]


def _front_plane(points: NDArray[np.float64], normals: NDArray[np.float64],
                 band: NDArray[np.bool_]) -> float | None:
    """y [m] of a drawer's front face from the outward-facing points of its ``band`` that lie
    beside the handle (|x − x_cabinet| beyond the handle's half-length), or None if too few."""
    cx, cy = CABINET_POSITION
    sx, sy = CABINET_SIZE[0] / 2, CABINET_SIZE[1] / 2
    dx = np.abs(points[:, 0] - cx)
    front = cy - sy
    face = (band & (dx > HANDLE_HALF[0] + 0.01) & (dx < sx - CABINET_WALL - 0.002)
            & (normals[:, 1] < -FACING)
            & (points[:, 1] > front - DRAWER_TRAVEL - 0.01) & (points[:, 1] < front + 0.005))
    if np.count_nonzero(face) < MIN_FRONT_POINTS:
        return None
    return float(np.median(points[face, 1]))


def fit_cabinet(points: NDArray[np.float64], normals: NDArray[np.float64],
                prior: dict[str, float] | None = None) -> CabinetFit:
    """Fit the cabinet to candidate points (those not already some other object's, and not the
    achromatic robot's).

    Args:
        points: candidate world points [m], shape (N, 3).
        normals: their unit normals, shape (N, 3) (zero rows where unknown).
        prior: openings [m] measured earlier, used for a drawer whose front is hidden now.

    Returns:
        the fit; ``parts`` index ``points``.
    """
    cx, cy = CABINET_POSITION
    sx, sy, height = CABINET_SIZE[0] / 2, CABINET_SIZE[1] / 2, CABINET_SIZE[2]
    front = cy - sy
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    in_x = np.abs(x - cx) <= sx + MARGIN_M
    in_box = (in_x & (y >= front - MARGIN_M) & (y <= cy + sy + MARGIN_M)
              & (z > ABOVE_TABLE_M) & (z <= height + MARGIN_M))
    if np.count_nonzero(in_box) < MIN_CABINET_POINTS:
        return CabinetFit(False, {}, {})
    taken = np.zeros(len(points), dtype=bool)
    openings: dict[str, float] = {}
    parts: dict[str, NDArray[np.int64]] = {}
    for slot in drawer_slots():
        band = in_x & (np.abs(z - slot.centre_z) <= slot.half_height + MARGIN_M)
        face_y = _front_plane(points, normals, band)
        if face_y is None and prior is not None and slot.name in prior:
            face_y = front - prior[slot.name]
        if face_y is None:
            continue
        openings[slot.name] = float(np.clip(front - face_y, 0.0, DRAWER_TRAVEL))
        reach = HANDLE_STANDOFF + HANDLE_HALF[1] + MARGIN_M
        outside = (np.abs(x - cx) <= sx - 0.003) & (y >= face_y - reach) & \
            (y <= max(face_y + 2 * CABINET_WALL, front + MARGIN_M))
        # an open drawer's inside, seen through the cabinet's front: between its walls, above
        # the shelf it slides on, up to its rear
        within = (np.abs(x - cx) <= sx - CABINET_WALL) & (y <= face_y + DRAWER_LENGTH_M) & \
            (z >= slot.centre_z - slot.half_height + 0.002)
        inside = band & ~taken & (outside | within)
        handle = inside & (y < face_y - 0.003) & (np.abs(x - cx) <= HANDLE_HALF[0] + MARGIN_M) \
            & (np.abs(z - slot.centre_z) <= 0.02)
        parts[f"{slot.name} drawer handle"] = np.flatnonzero(handle)
        parts[f"{slot.name} drawer"] = np.flatnonzero(inside & ~handle)
        taken |= inside
    parts["cabinet"] = np.flatnonzero(in_box & ~taken)
    return CabinetFit(True, openings, parts)


__all__ = ["CabinetFit", "fit_cabinet"]
