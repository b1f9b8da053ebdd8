"""The axis a drawer slides along, from what the cameras see of it: the outward normal of its
front face."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from voxposer import catalog
from voxposer.errors import VoxPoserError
from voxposer.perception.detect import DetectedObject

#: A drawer's front faces within this angle [deg] of the direction from its centre to its
#: handle (the handle sits on the front).
FRONT_CONE_DEG = 60.0
#: Below this horizontal centre-to-handle distance [m] the direction says nothing.
MIN_HANDLE_OFFSET_M = 0.005
#: A handle whose points' horizontal variance is this many times larger along one axis than
#: across it is a bar (the cabinet's: ~20 exact, ≥ 8 with noisy depth).
BAR_ELONGATION = 4.0
#: Fewer handle points than this say nothing of its shape.
MIN_BAR_POINTS = 20


def dominant_normal(normals: NDArray[np.float64], cone_deg: float = 25.0, rounds: int = 3,
                    toward: NDArray[np.float64] | None = None) -> NDArray[np.float64] | None:
    """The horizontal direction most of ``normals`` (shape (N, 3)) face, as a unit vector, shape
    (3,): among the sideways-facing ones (|n_z| < 0.5), start from the most populated 10° sector
    of azimuth, then ``rounds`` times take the mean of those within ``cone_deg`` of the last
    estimate. With ``toward`` (a horizontal unit direction, shape (3,)), the starting sector is
    the most populated among the normals within :data:`FRONT_CONE_DEG` of it (among all when
    none is); the means then take all of them. None when no normal faces sideways."""
    flat = normals[(np.linalg.norm(normals, axis=1) > 0.5) & (np.abs(normals[:, 2]) < 0.5)]
    flat = flat * np.array([1.0, 1.0, 0.0])
    if len(flat) == 0:
        return None
    flat /= np.linalg.norm(flat, axis=1, keepdims=True)
    seeds = flat
    if toward is not None:
        ahead = flat[flat @ toward > np.cos(np.radians(FRONT_CONE_DEG))]
        seeds = ahead if len(ahead) else flat
    counts = np.bincount(((np.arctan2(seeds[:, 1], seeds[:, 0]) + np.pi) // np.radians(10.0))
                         .astype(int) % 36, minlength=36)
    peak = (int(np.argmax(counts)) + 0.5) * np.radians(10.0) - np.pi
    estimate = np.array([np.cos(peak), np.sin(peak), 0.0])
    for _ in range(rounds):
        length = float(np.linalg.norm(estimate))
        if length < 1e-9:
            return None
        estimate /= length
        near = flat[flat @ estimate > np.cos(np.radians(cone_deg))]
        if len(near) == 0:
            break
        estimate = near.mean(axis=0)
    length = float(np.linalg.norm(estimate))
    return estimate / length if length > 1e-9 else None


def drawer_front_normal(detect: Callable[[str], DetectedObject], drawer: str
                        ) -> NDArray[np.float64] | None:
    """The outward normal of ``drawer``'s front, shape (3,), from ``detect``'s objects.

    With a visible bar handle (its points' horizontal spread at least :data:`BAR_ELONGATION`
    times longer one way than the other): level and square to the bar, on the handle's side of
    the drawer's centre. Per-point normals of noisy depth are near uniform over azimuth, and
    an open drawer's side walls (facing 90° away) can outnumber its front's; the bar's long
    axis stays within ~2° with the sensor noise of the simulated cameras. Otherwise the
    dominant sideways normal (:func:`dominant_normal`), started on the handle's side when the
    handle is seen.
    """
    seen = detect(drawer)
    handle = _handle_of(detect, drawer)
    toward, square = None, None
    if handle is not None:
        offset = (np.asarray(handle.position) - np.asarray(seen.position)) * [1.0, 1.0, 0.0]
        if np.linalg.norm(offset) > MIN_HANDLE_OFFSET_M:
            toward = offset / np.linalg.norm(offset)
        square = _square_to_bar(np.asarray(handle.points, dtype=np.float64))
    front = None
    if square is None or toward is None:
        front = dominant_normal(np.asarray(seen.normals, dtype=np.float64), toward=toward)
    side = toward if toward is not None else front  # which way the bar's normal points
    if square is not None and side is not None:
        return square if square @ side >= 0 else -square
    return front


def _handle_of(detect: Callable[[str], DetectedObject], drawer: str) -> DetectedObject | None:
    """The detected handle of catalog drawer ``drawer``, or None (no such part, not seen)."""
    try:
        names = [n for n in catalog.family(drawer) if catalog.object_named(n).kind == "handle"]
    except KeyError:  # not a catalog drawer: no known handle
        return None
    for name in names:
        try:
            return detect(name)
        except VoxPoserError:  # not visible (or not detected)
            continue
    return None


def _square_to_bar(points: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """The level unit direction square to a bar's long axis (sign arbitrary), shape (3,), from
    its points [m], shape (N, 3); None unless they spread horizontally along one axis
    (:data:`BAR_ELONGATION`) over at least :data:`MIN_BAR_POINTS` points."""
    if len(points) < MIN_BAR_POINTS:
        return None
    xy = points[:, :2] - points[:, :2].mean(axis=0)
    spread, axes = np.linalg.eigh(np.cov(xy.T))
    if spread[1] < BAR_ELONGATION * max(float(spread[0]), 1e-12):
        return None
    along = axes[:, 1]
    return np.array([-along[1], along[0], 0.0])


__all__ = ["BAR_ELONGATION", "FRONT_CONE_DEG", "MIN_BAR_POINTS", "MIN_HANDLE_OFFSET_M",
           "dominant_normal", "drawer_front_normal"]
