"""Coloured blocks and lines from a fused cloud of colour-labelled points: 3-D clusters per
colour word, told apart by shape.

A line is flat on the table (its paint is 2 mm thick); a block is a compact 5 cm cube, resting
on the table or carried. For each colour word: the points raised above the table cluster into
the block (the largest compact cluster that stands above a line's noisy paint, with touching
fragments), the block's flat points just above the table stay with it, and the remaining flat
points are the line (all its fragments: an object lying across a line cuts it in two). A gray
block is the one compact achromatic cluster that is not part of the (equally gray) robot; a gray
line a thin flat achromatic strip. When the gray block touches the robot (the gripper closing on
it, pushing it), its points join the robot's and no compact cluster is left: then, if the block
was found before, it is tracked — the raised gray points in a block-sized box around where it
was, re-centred on them (:data:`TRACK_HALF_M`). Likewise a gray line that joins other flat gray
points (a shadow, the robot's base) is kept from where it lay (lines do not move): the flat gray
points in the strip it occupied (:data:`LINE_TRACK_HALF_WIDTH_M`). A gray line found before is
looked for there first: with a block covering part of it, another thin flat gray strip (30–50 cm
away: the robot's base, a shadow) outgrew its uncovered fragments and was taken for it (dev
records).
"""

from __future__ import annotations

from typing import Final

import numpy as np
from numpy.typing import NDArray

from voxposer.catalog import COLOR_NAMES
from voxposer.perception.clusters import box_gap, cluster_points
from voxposer.perception.colour_names import GRAY

#: Points below this height [m] lie flat on the table (a line's top is at 2 mm).
FLAT_Z_M: Final = 0.005
#: Points above this height [m] belong to a block, never to a line, whatever the depth noise.
CORE_Z_M: Final = 0.02
#: A block's box is at most this large along any axis [m] (a 5 cm cube seen from any side).
BLOCK_MAX_EXTENT_M: Final = 0.09
#: Fewest points of a block's main cluster and of any line fragment.
MIN_BLOCK_POINTS: Final = 20
#: Fewest points above :data:`CORE_Z_M` in a block's main cluster: a block stands 5 cm tall,
#: while a stretch of line whose paint the depth noise lifts above :data:`FLAT_Z_M` is as
#: compact but stays below it (without this, such a stretch was found as a block of the
#: line's colour and cut from the line).
MIN_CORE_POINTS: Final = 5
MIN_LINE_POINTS: Final = 8
#: Fragments this close [m] to a block's main cluster are part of it.
FRAGMENT_GAP_M: Final = 0.02
#: Line fragments within this distance [m] of the largest fragment's centre are one line.
LINE_REACH_M: Final = 0.22
#: A gray line is at most this wide [m] (lines are 1.2 cm wide) and this long [m].
LINE_MAX_WIDTH_M: Final = 0.03
LINE_MAX_LENGTH_M: Final = 0.24
#: A gray block's cluster spans at least this much in x and in y [m] (its top face is 5 cm
#: square at any yaw); a gray finger of the robot, cut off from its hand, spans less.
GRAY_MIN_SPAN_M: Final = 0.03
#: A tracked block's points: within this distance [m] of its centre along each axis (half its
#: 5 cm size plus a margin), the box re-centred on them this many times (the block moved).
TRACK_HALF_M: Final = 0.03
TRACK_STEPS: Final = 3
#: A tracked line's points: within this distance [m] across its previous axis (its 1.2 cm
#: width plus a margin) and within its previous half-length plus this along it.
LINE_TRACK_HALF_WIDTH_M: Final = 0.012
LINE_TRACK_END_M: Final = 0.01


def line_prior(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """A line's footprint from its points (shape (N, 3)), for tracking: its centre [m] (3),
    unit axis in the table plane (3) and half-length [m] (1), shape (7,)."""
    centre = points.mean(axis=0)
    xy = points[:, :2] - centre[:2]
    axis2 = np.linalg.svd(xy, full_matrices=False)[2][0]
    half = float(np.abs(xy @ axis2).max())
    return np.concatenate([centre, [axis2[0], axis2[1], 0.0], [half]])


def _compact(points: NDArray[np.float64]) -> bool:
    return bool(np.all(np.ptp(points, axis=0) <= BLOCK_MAX_EXTENT_M))


def _block_members(points: NDArray[np.float64], raised: NDArray[np.bool_], gray: bool
                   ) -> NDArray[np.bool_]:
    """Which of one colour's ``points`` (shape (N, 3)) are its block: the largest compact
    cluster of the raised points, touching fragments, and flat points under its footprint.
    For ``gray`` the cluster must also be broad (:data:`GRAY_MIN_SPAN_M`), not a finger.
    When no raised cluster is compact — a block on its own colour's line, whose paint the depth
    noise lifts above :data:`FLAT_Z_M` along its length and joins to the block — the cluster
    is looked for among the points above :data:`CORE_Z_M` instead, and every point under its
    footprint below that height joins it (not for gray, whose raised points include the
    robot's: a gray block is tracked from where it was instead)."""
    members = _compact_cluster(points, raised, gray)
    low = FLAT_Z_M
    if not members.any() and not gray:  # gray: the robot's raised points too (tracked instead)
        members = _compact_cluster(points, raised & (points[:, 2] >= CORE_Z_M), gray)
        low = CORE_Z_M
    if not members.any():
        return members
    block = points[members]
    lo, hi = block.min(axis=0)[:2] - 0.006, block.max(axis=0)[:2] + 0.006
    under = (points[:, 2] < low) & np.all((points[:, :2] >= lo) & (points[:, :2] <= hi), axis=1)
    return members | under


def _compact_cluster(points: NDArray[np.float64], subset: NDArray[np.bool_], gray: bool
                     ) -> NDArray[np.bool_]:
    """The largest compact and tall (:data:`MIN_CORE_POINTS`; for ``gray`` also broad)
    cluster of ``points[subset]`` with the fragments that touch it and keep it compact, as a
    mask over ``points`` (empty: none)."""
    members = np.zeros(len(points), dtype=bool)
    idx = np.flatnonzero(subset)
    clusters = cluster_points(points[idx])
    main = None
    for k in range(clusters.n_clusters):
        if clusters.sizes[k] < MIN_BLOCK_POINTS:
            break
        pts = points[idx[clusters.labels == k]]
        broad = not gray or bool(np.all(np.ptp(pts[:, :2], axis=0) >= GRAY_MIN_SPAN_M))
        tall = np.count_nonzero(pts[:, 2] >= CORE_Z_M) >= MIN_CORE_POINTS
        if _compact(pts) and broad and tall:
            main = k
            break
    if main is None:
        return members
    core = points[idx[clusters.labels == main]]
    for k in range(clusters.n_clusters):
        pts = points[idx[clusters.labels == k]]
        if k == main or (box_gap(core, pts) <= FRAGMENT_GAP_M and _compact(np.vstack([core, pts]))):
            members[idx[clusters.labels == k]] = True
    return members


def _tracked_members(points: NDArray[np.float64], raised: NDArray[np.bool_],
                     prior: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Which of one colour's ``points`` (shape (N, 3)) lie in a block-sized box around the
    block's previous centre ``prior`` [m], shape (3,), re-centred on them (empty: too few)."""
    centre = np.asarray(prior, dtype=np.float64)
    inside = np.zeros(len(points), dtype=bool)
    for _ in range(TRACK_STEPS):
        inside = raised & np.all(np.abs(points - centre) <= TRACK_HALF_M, axis=1)
        if inside.sum() < MIN_BLOCK_POINTS:
            return np.zeros(len(points), dtype=bool)
        centre = points[inside].mean(axis=0)
    return inside


def _tracked_line(points: NDArray[np.float64], flat: NDArray[np.bool_],
                  prior: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Which of one colour's flat ``points`` lie in the strip a line occupied (``prior``:
    :func:`line_prior`); empty with too few."""
    centre, axis, half = prior[:3], prior[3:6], float(prior[6])
    rel = points[:, :2] - centre[:2]
    along = rel @ axis[:2]
    across = np.abs(rel @ np.array([-axis[1], axis[0]]))
    inside = flat & (np.abs(along) <= half + LINE_TRACK_END_M) & (across <= LINE_TRACK_HALF_WIDTH_M)
    return inside if inside.sum() >= MIN_LINE_POINTS else np.zeros(len(points), dtype=bool)


def _thin_strip(points: NDArray[np.float64]) -> bool:
    """Whether points (shape (N, 3)) form a strip no wider and longer than a line."""
    xy = points[:, :2] - points[:, :2].mean(axis=0)
    axes = np.linalg.svd(xy, full_matrices=False)[2]
    spans = np.ptp(xy @ axes.T, axis=0)
    return bool(spans[0] <= LINE_MAX_LENGTH_M and spans[-1] <= LINE_MAX_WIDTH_M)


def _line_members(points: NDArray[np.float64], flat: NDArray[np.bool_], gray: bool
                  ) -> NDArray[np.bool_]:
    """Which of one colour's flat ``points`` are its line: every fragment within reach of the
    largest (for gray, only thin strips count)."""
    members = np.zeros(len(points), dtype=bool)
    idx = np.flatnonzero(flat)
    clusters = cluster_points(points[idx])
    keep = [k for k in range(clusters.n_clusters) if clusters.sizes[k] >= MIN_LINE_POINTS
            and (not gray or _thin_strip(points[idx[clusters.labels == k]]))]
    if not keep:
        return members
    centre = points[idx[clusters.labels == keep[0]]].mean(axis=0)
    for k in keep:
        pts = points[idx[clusters.labels == k]]
        if np.linalg.norm(pts.mean(axis=0) - centre) <= LINE_REACH_M:
            members[idx[clusters.labels == k]] = True
    return members


def find_blocks_and_lines(points: NDArray[np.float64], colours: NDArray[np.int32],
                          priors: dict[str, NDArray[np.float64]] | None = None
                          ) -> dict[str, NDArray[np.int64]]:
    """Blocks and lines among colour-labelled points.

    Args:
        points: fused world points [m], shape (N, 3) (the table top is z = 0).
        colours: colour word of each point, shape (N,): an index into :data:`COLOR_NAMES`, or
            negative for none.
        priors: what was found before: block name → its centre [m], shape (3,); line name →
            its footprint (:func:`line_prior`); the gray block and line are tracked from there
            when they join other gray points (see the module docs).

    Returns:
        object name ("blue block", "gray line") → indices into ``points`` of its points, for
        every object found.
    """
    found: dict[str, NDArray[np.int64]] = {}
    for k, colour in enumerate(COLOR_NAMES):
        idx = np.flatnonzero(colours == k)
        if len(idx) == 0:
            continue
        pts = points[idx]
        raised = pts[:, 2] >= FLAT_Z_M
        block = _block_members(pts, raised, gray=k == GRAY)
        prior = (priors or {}).get(f"{colour} block")
        if k == GRAY and not block.any() and prior is not None:
            block = _tracked_members(pts, raised, prior)
        if block.any():
            found[f"{colour} block"] = idx[block]
        line_was = (priors or {}).get(f"{colour} line")
        line = np.zeros(len(pts), dtype=bool)
        if k == GRAY and line_was is not None:  # lines do not move: where it lay first
            line = _tracked_line(pts, ~raised & ~block, line_was)
        if not line.any():
            line = _line_members(pts, ~raised & ~block, gray=k == GRAY)
        if line.any():
            found[f"{colour} line"] = idx[line]
    return found


__all__ = ["FLAT_Z_M", "find_blocks_and_lines", "line_prior"]
