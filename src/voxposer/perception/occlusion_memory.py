"""Remembering the parts of an object that another object now hides from every camera.

A block pushed onto the end of a line covers that end: no camera sees the line under the block,
so a detection from the current views alone is short by the covered part, its box shrinks and a
target computed from it ("the far end of the line") jumps back behind the block — the push then
chases a target that moves with it. Real mapping systems keep what they cannot see until they see
through it (free-space carving); :class:`OcclusionMemory` does the same per object:

a point the object had last time is kept when every camera whose image it falls in shows
*another* object's surface in front of it (nearer by more than ``depth_tol_m``), and dropped as
soon as one camera does not: it sees through the point (a farther surface or the background at
its pixel), sees it again or a surface at its depth (a table where a moved block stood), or sees
the object's own surface in front of it (the object moved or turned). A point that falls in no
camera's image is dropped. An object that moved (:func:`is_still`) forgets everything: the hand
carrying a block hides the block's old places all the way. The cost: a hidden point within about ``depth_tol_m`` of the occluder's
edge, seen at a grazing angle, is lost.

An object no camera sees at all now (a block under the hand that is about to push it) is
recalled whole (:meth:`OcclusionMemory.recall`) when at least ``RECALL_FRACTION`` of the points
it had are hidden behind other objects by the same rule — it is where it was, covered — and not
when the cameras see through its place (it left). The fraction, not every point: the sensor
model drops depth at an occluder's edges and on dark surfaces, which reads as seeing through.

Only objects that keep their shape and lie where they were left take part (blocks and lines): a
drawer, a fixture or the robot change what hides them in ways these rules do not cover.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.detect import DetectedObject, object_from_points
from voxposer.perception.point_cloud import DepthView

#: Depth difference [m] below which two surfaces along a camera ray count as the same one.
DEPTH_TOL_M = 0.01
#: An object is still (its memory holds) when this fraction of its visible points lie within
#: ``STILL_TOL_M`` [m] of the points it had: a static surface seen from static cameras gives the
#: same points again, up to the depth noise — a consumer RGB-D camera's σ ≈ 4 mm along the ray
#: at 1.2 m scatters a still block's points so that only about half lie within 2 mm of the last
#: observation's, 99 % within 6 mm. A carried or pushed block (≥ 1 cm per push) fails this, so the
#: hand that moves with it (and hides its old places) leaves no trail of stale points.
STILL_FRACTION = 0.9
STILL_TOL_M = 0.005
#: An object wholly unseen now is recalled when at least this fraction of its remembered points
#: are hidden behind other objects.
RECALL_FRACTION = 0.5
#: Kinds of objects (:data:`voxposer.catalog.Kind`) whose hidden parts are remembered.
REMEMBERED_KINDS = frozenset({"block", "line"})


def _project(points: NDArray[np.float64], view: DepthView
             ) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.float64], NDArray[np.bool_]]:
    """Pixel row, column and camera depth [m] of world ``points`` (N, 3) in ``view``, and which
    fall inside its image in front of it (shape (N,) each)."""
    ext = np.asarray(view.extrinsics, dtype=np.float64)
    rot, origin = ext[:3, :3], ext[:3, 3]
    cam = (points - origin) @ rot  # world → camera: R^T (p - t)
    z = cam[:, 2]
    k = np.asarray(view.intrinsics, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.rint(k[0, 0] * cam[:, 0] / z + k[0, 2])
        v = np.rint(k[1, 1] * cam[:, 1] / z + k[1, 2])
    h, w = view.depth.shape
    inside = (z > 1e-6) & np.isfinite(u) & np.isfinite(v) & (u >= 0) & (u < w) & (v >= 0) & (v < h)
    rows = np.where(inside, v, 0).astype(np.intp)
    cols = np.where(inside, u, 0).astype(np.intp)
    return rows, cols, z, inside


def _own_pixels(visible: NDArray[np.float64], view: DepthView, tol: float) -> NDArray[np.bool_]:
    """Pixels of ``view`` (shape (H, W)) whose surface is one of the ``visible`` points (N, 3)."""
    own = np.zeros(view.depth.shape, dtype=bool)
    if len(visible) == 0:
        return own
    rows, cols, z, inside = _project(visible, view)
    depth = np.asarray(view.depth, dtype=np.float64)[rows, cols]
    on_surface = inside & (np.abs(depth - z) <= tol)
    own[rows[on_surface], cols[on_surface]] = True
    return own


def hidden_by_others(remembered: NDArray[np.float64], visible: NDArray[np.float64],
                     views: Sequence[DepthView], depth_tol_m: float = DEPTH_TOL_M
                     ) -> NDArray[np.bool_]:
    """Which ``remembered`` points (N, 3) [m] of an object are hidden now behind other objects.

    Args:
        remembered: the object's points from an earlier observation [m], shape (N, 3).
        visible: its points in the current views [m], shape (M, 3).
        views: the current depth views (intrinsics, camera-to-world extrinsics, depth [m]).
        depth_tol_m: surfaces closer than this along a ray are one surface [m].

    Returns:
        Shape (N,), bool: True where every camera whose image the point falls in (at least one)
        shows another object's surface in front of it, nearer by more than ``depth_tol_m``.
    """
    n = len(remembered)
    hidden = np.zeros(n, dtype=bool)
    vetoed = np.zeros(n, dtype=bool)
    for view in views if n else ():
        rows, cols, z, inside = _project(remembered, view)
        depth = np.asarray(view.depth, dtype=np.float64)[rows, cols]
        depth = np.where(np.isfinite(depth), depth, np.inf)
        own = _own_pixels(visible, view, depth_tol_m)[rows, cols]
        behind_other = (depth < z - depth_tol_m) & ~own
        vetoed |= inside & ~behind_other
        hidden |= inside & behind_other
    return hidden & ~vetoed


def is_still(remembered: NDArray[np.float64], visible: NDArray[np.float64],
             tol_m: float = STILL_TOL_M, fraction: float = STILL_FRACTION) -> bool:
    """Whether an object with ``visible`` points (M, 3) [m] now is where its ``remembered``
    points (N, 3) [m] were: at least ``fraction`` of the visible ones lie within ``tol_m`` [m]
    of a remembered one."""
    if len(visible) == 0 or len(remembered) == 0:
        return False
    dist, _ = cKDTree(remembered).query(visible, distance_upper_bound=tol_m)
    return float(np.mean(np.isfinite(dist))) >= fraction


class OcclusionMemory:
    """Per-object points kept while other objects hide them (module docs).

    Call :meth:`extend` once per object and observation with the object as detected in the
    current views; it returns it with the remembered hidden points added (box, centre,
    occupancy and normal recomputed) and remembers the union.

    Args:
        depth_tol_m: see :func:`hidden_by_others` [m].
    """

    def __init__(self, depth_tol_m: float = DEPTH_TOL_M) -> None:
        if not np.isfinite(depth_tol_m) or depth_tol_m <= 0:
            raise ValueError(f"depth_tol_m must be a positive finite distance [m]; got {depth_tol_m!r}")
        self.depth_tol_m = float(depth_tol_m)
        self._held: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}
        self._time_s = -np.inf

    def extend(self, found: DetectedObject, views: Sequence[DepthView], grid: VoxelGrid,
               time_s: float) -> DetectedObject:
        """``found`` (detected in ``views``, observed at ``time_s`` [s]) with the points it had
        before that other objects now hide; remembers the union. An observation older than the
        last one (a reset: the clock started again) forgets everything first."""
        if time_s < self._time_s:
            self.forget()
        self._time_s = time_s
        points, normals = found.points, found.normals
        before = self._held.get(found.name)
        if before is not None and is_still(before[0], points):
            keep = hidden_by_others(before[0], points, views, self.depth_tol_m)
            if np.any(keep):
                points = np.concatenate([points, before[0][keep]])
                normals = np.concatenate([normals, before[1][keep]])
                found = object_from_points(found.name, points, normals, grid)
        self._held[found.name] = (points, normals)
        return found

    def recall(self, name: str, views: Sequence[DepthView], grid: VoxelGrid, time_s: float
               ) -> DetectedObject | None:
        """``name`` as last seen, when no camera sees any of it in ``views`` (observed at
        ``time_s`` [s]) and at least :data:`RECALL_FRACTION` of its remembered points are hidden
        behind other objects (module docs); None otherwise (never seen, it left, or a reset).
        What is remembered does not change."""
        if time_s < self._time_s:
            self.forget()
        self._time_s = time_s
        before = self._held.get(name)
        if before is None or len(before[0]) == 0:
            return None
        hidden = hidden_by_others(before[0], np.zeros((0, 3)), views, self.depth_tol_m)
        if float(np.mean(hidden)) < RECALL_FRACTION:
            return None
        return object_from_points(name, before[0], before[1], grid)

    def forget(self) -> None:
        """Drop everything remembered (a new scene)."""
        self._held.clear()
        self._time_s = -np.inf


__all__ = [
    "DEPTH_TOL_M",
    "RECALL_FRACTION",
    "REMEMBERED_KINDS",
    "STILL_FRACTION",
    "STILL_TOL_M",
    "OcclusionMemory",
    "hidden_by_others",
    "is_still",
]
