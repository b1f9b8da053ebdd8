"""Measures over the paths a sub-task executed, for the intent checks' path conditions.

A path is an (N, 3) array of positions [m]; a timed path adds the (N,) times [s] of its samples.
Boxes are axis-aligned, given by their ``lo`` and ``hi`` corners [m], shape (3,).
"""

from __future__ import annotations

from itertools import pairwise
from typing import Final, NamedTuple

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.line_progress import on_line_progress

#: how far [m] a point may lie across a side's face and still count as on that side.
SIDE_SLACK_M: Final = 0.01
#: how far [m] beyond a box's extent a point still counts as level with it (passing it).
LEVEL_MARGIN_M: Final = 0.01
#: speed samples in the first this many seconds of a motion are left out (acceleration) [s] …
SKIP_START_S: Final = 0.2
#: … and those within this distance of where the motion ends (deceleration) [m].
SKIP_END_M: Final = 0.03
#: a gap between samples longer than this [s] is a pause (gripper, settling), not motion.
MAX_GAP_S: Final = 0.05
#: an object's path (one sample per replan) is filled in to points at most this far apart [m].
DENSE_SPACING_M: Final = 0.005


def box_gap(points: NDArray[np.float64], lo: NDArray[np.float64], hi: NDArray[np.float64],
            half: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """Distance [m] from each point (N, 3) to the box, 0 inside; with ``half`` (3,), the
    half-extent of a box centred on each point, the gap between the two boxes' faces."""
    pad = np.zeros(3) if half is None else np.asarray(half, float)
    gap = np.maximum(np.maximum(lo - pad - points, points - pad - hi), 0.0)
    return np.asarray(np.linalg.norm(gap, axis=1), dtype=np.float64)


#: a box counts as compact (a block: judged by its footprint's inscribed circle, whatever its
#: turn) when its horizontal sides are at most this long [m] and within this ratio.
COMPACT_SIDE_M: Final = 0.12
COMPACT_RATIO: Final = 1.5


def is_compact(lo: NDArray[np.float64], hi: NDArray[np.float64]) -> bool:
    """Whether the box ``lo``–``hi`` (3,) [m] is a compact object (see :data:`COMPACT_SIDE_M`)."""
    sides = np.asarray(hi, float)[:2] - np.asarray(lo, float)[:2]
    return bool(np.all(sides > 0) and sides.max() <= COMPACT_SIDE_M
                and sides.max() <= COMPACT_RATIO * sides.min())


def compact_gap(points: NDArray[np.float64], half: NDArray[np.float64],
                lo: NDArray[np.float64], hi: NDArray[np.float64]) -> NDArray[np.float64]:
    """Gap [m] between a compact object centred on each point (N, 3), half-extent ``half``
    (3,), and the compact box ``lo``–``hi``, shape (N,): horizontally between the circles
    inscribed in the two footprints (an axis-aligned box of a turned block overstates it by
    up to 41%, and two blocks corner to corner are farther apart than their boxes say),
    vertically between their faces."""
    lo, hi, half = np.asarray(lo, float), np.asarray(hi, float), np.asarray(half, float)
    centre, other = (lo + hi) / 2.0, (hi - lo) / 2.0
    d = np.asarray(points, float).reshape(-1, 3) - centre
    flat = np.maximum(np.linalg.norm(d[:, :2], axis=1) - half[:2].min() - other[:2].min(), 0.0)
    up = np.maximum(np.abs(d[:, 2]) - half[2] - other[2], 0.0)
    return np.asarray(np.hypot(flat, up), dtype=np.float64)


class SidePass(NamedTuple):
    """How a path passed a box on one side: ``level`` samples beside it, and ``margin`` [m],
    the least distance beyond the side's face over those samples (negative: across it)."""

    level: int
    margin: float


def side_pass(path: NDArray[np.float64], lo: NDArray[np.float64], hi: NDArray[np.float64],
              signs: dict[int, int]) -> SidePass:
    """Where ``path`` (N, 3) is level with the box (within its extent + 1 cm on every horizontal
    axis the side does not name), how far it stays beyond the faces ``signs`` names ({axis:
    ±1}, e.g. {1: -1} for the left face, {2: 1} for the top)."""
    level = np.ones(len(path), dtype=bool)
    for axis in (0, 1):
        if axis not in signs:
            level &= (path[:, axis] >= lo[axis] - LEVEL_MARGIN_M) & \
                     (path[:, axis] <= hi[axis] + LEVEL_MARGIN_M)
    if not np.any(level) or not signs:
        return SidePass(int(np.sum(level)), float("nan"))
    beyond = np.stack([sign * (path[level, axis] - (hi[axis] if sign > 0 else lo[axis]))
                       for axis, sign in signs.items()])
    return SidePass(int(np.sum(level)), float(np.min(np.min(beyond, axis=0))))


def motion_speeds(path: NDArray[np.float64], times: NDArray[np.float64]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Speeds [m/s] between consecutive samples of one timed path, and the midpoints [m] they
    belong to, leaving out the motion's first :data:`SKIP_START_S`, its last
    :data:`SKIP_END_M` and pauses: shapes (K,), (K, 3)."""
    if len(path) < 2:
        return np.zeros(0), np.zeros((0, 3))
    step = np.diff(path, axis=0)
    dt = np.diff(times)
    mid = (path[1:] + path[:-1]) / 2.0
    moved = np.linalg.norm(path - path[0], axis=1) > 0.01
    start = times[int(np.argmax(moved))] if np.any(moved) else np.inf
    keep = ((dt > 0) & (dt < MAX_GAP_S) & (times[1:] >= start + SKIP_START_S)
            & (np.linalg.norm(mid - path[-1], axis=1) > SKIP_END_M))
    speed = np.linalg.norm(step[keep], axis=1) / dt[keep]
    return speed, mid[keep]


def speed_band(scale: float) -> tuple[float, float]:
    """The band of measured/default speed ratios that counts as moving at ``scale``: within a
    factor 1.6 of it for ``scale`` ≤ 1 (0.25 → [0.16, 0.4]); a speed-up counts from a quarter
    of the way there on (2 → [1.25, ∞), 3 → [1.5, ∞)), since the arm's joint limits cap it."""
    if scale > 1.0:
        return 1.0 + (scale - 1.0) / 4.0, float("inf")
    return scale / 1.6, scale * 1.6


__all__ = ["COMPACT_RATIO", "COMPACT_SIDE_M", "SidePass", "box_gap", "compact_gap",
           "is_compact", "line_progress", "motion_speeds", "side_pass", "speed_band"]


def densify(path: NDArray[np.float64], spacing: float = DENSE_SPACING_M) -> NDArray[np.float64]:
    """``path`` (N, 3) [m] with points added on the straight segments between its samples so
    that none is longer than ``spacing`` [m]: an object observed once per replan moves about
    straight in between, and its closest approach to something may fall between two samples."""
    path = np.asarray(path, dtype=np.float64).reshape(-1, 3)
    if len(path) < 2:
        return path
    parts = [path[:1]]
    for a, b in pairwise(path):
        n = max(1, int(np.ceil(np.linalg.norm(b - a) / spacing)))
        parts.append(a + np.outer(np.arange(1, n + 1) / n, b - a))
    return np.concatenate(parts)


def face_shift(before: tuple[NDArray[np.float64], NDArray[np.float64]],
               after: tuple[NDArray[np.float64], NDArray[np.float64]]) -> NDArray[np.float64]:
    """How far a box moved [m], shape (3,), measured by its faces: per axis the larger shift of
    its two faces (``before``, ``after``: (lo, hi) corners). For a drawer, whose body slides into
    the cabinet out of the cameras' view, the front face moves by the drawer's travel while the
    centre of what is still visible moves far less."""
    d_lo, d_hi = after[0] - before[0], after[1] - before[1]
    return np.where(np.abs(d_hi) > np.abs(d_lo), d_hi, d_lo)


def line_progress(points: NDArray[np.float64], lo: NDArray[np.float64], hi: NDArray[np.float64],
                  band: float) -> float:
    """How far [m] the path ``points`` (N, 3) advanced along the long horizontal axis of the
    box [lo, hi] (a line on the table) without leaving it: the largest span along the axis of a
    run of consecutive points within ``band`` [m] of the axis."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    axis = int(np.argmax((hi - lo)[:2]))
    centre = (lo + hi) / 2.0
    along = points[:, axis] - centre[axis]
    lateral = np.abs(points[:, 1 - axis] - centre[1 - axis])
    return on_line_progress(along, lateral, band)
