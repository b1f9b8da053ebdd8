"""Labels carried from one observation to the next: the pixel perception's tracker.

A full detection (colour clusters for blocks and lines, the cabinet fit:
:func:`~voxposer.perception.pixel_labels.label_pixels`) costs tens of milliseconds per
observation, yet between two replans (0.2 s) the objects barely move: a pushed block about a
centimetre. As the paper's pipeline detects once and lets a video tracker (XMem) carry the masks,
:func:`track_labels` carries each object's label from the last labelled cloud to the new one: a
new point takes the label of the last cloud's object point in its voxel of the workspace grid,
or in one beside it (``reach_voxels``), when its colour word fits that object (a block or a line:
its own colour; a cabinet part: any hue but gray). The table, the robot and the gripper are then
labelled as after a detection (:func:`~voxposer.perception.pixel_labels.finish_labels`).

Tracking gives up (returns None: the caller detects afresh) when

* an object kept fewer than ``keep_fraction`` of the points it had in the last cloud (it moved
  farther than the reach, or something now hides it);
* more points of a chromatic colour are left unexplained than at the last detection, by more
  than ``unexplained_margin`` (an object came into view, or moved beyond reach);
* the end effector is within ``near_cabinet_m`` of a cabinet part (it may be moving a drawer,
  whose opening only the cabinet fit measures);
* a point carried as a gray object (the gray block or line) lies around the gripper: the gray
  gripper's points beside it would be taken for it, or the object's own points dropped as the
  gripper's, a few at each step, until its centre is off (only the detection's track of it, the
  colour-cluster geometry, parts the two).

How often the caller detects anyway (``redetect_s``) is its own rule
(:class:`~voxposer.perception.colour_depth.ColourDepthPerceiver`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from voxposer import catalog
from voxposer.catalog import NO_OBJECT
from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.colour_names import GRAY
from voxposer.perception.observation import Observation
from voxposer.perception.pixel_labels import (
    PixelLabels,
    ViewClouds,
    colour_cloud,
    finish_labels,
    gripper_mask,
    object_tracks,
)
from voxposer.perception.point_cloud import PointCloud

#: label → the colour word its points must carry: a block's or line's colour index, or
#: :data:`_ANY_HUE` for cabinet parts; labels absent here (table, robot, gripper) are not carried.
_ANY_HUE: Final = -2
_CARRIED: Final[dict[int, int]] = {
    k: (catalog.COLOR_NAMES.index(o.colour) if o.colour is not None else _ANY_HUE)
    for k, o in enumerate(catalog.OBJECTS) if o.kind in ("block", "line", "cabinet", "drawer",
                                                         "handle")}
#: :data:`_CARRIED` as a lookup array over every label (:data:`_NOT_CARRIED`: not carried).
_NOT_CARRIED: Final = -3
_WANTED: Final = np.full(len(catalog.OBJECTS), _NOT_CARRIED, dtype=np.int32)
_WANTED[list(_CARRIED)] = list(_CARRIED.values())
_CABINET: Final = frozenset(catalog.label_of(n) for n in catalog.family("cabinet"))


@dataclass(frozen=True)
class LabelTrackingConfig:
    """When the pixel perception carries labels instead of detecting.

    Attributes:
        redetect_s: a full detection at least this often [s of observation time].
        reach_voxels: how far [voxels of the workspace grid, per axis] a point may lie from the
            last cloud's point whose label it takes (1: the 26 neighbours).
        keep_fraction: an object keeping fewer than this share of its last points is lost.
        unexplained_margin: chromatic points left unexplained beyond the last detection's count
            that make tracking give up [points].
        near_cabinet_m: the end effector this close [m] to a cabinet part: detect afresh.
    """

    redetect_s: float = 1.0
    reach_voxels: int = 1
    keep_fraction: float = 0.6
    unexplained_margin: int = 40
    near_cabinet_m: float = 0.15

    def __post_init__(self) -> None:
        for name, value, ok in (
                ("redetect_s", self.redetect_s, self.redetect_s > 0),
                ("reach_voxels", self.reach_voxels,
                 isinstance(self.reach_voxels, int) and 0 <= self.reach_voxels <= 3),
                ("keep_fraction", self.keep_fraction, 0 <= self.keep_fraction <= 1),
                ("unexplained_margin", self.unexplained_margin, self.unexplained_margin >= 0),
                ("near_cabinet_m", self.near_cabinet_m, self.near_cabinet_m >= 0)):
            if not ok:
                raise ConfigError(f"LabelTrackingConfig.{name}={value!r} is out of range: "
                                  "redetect_s > 0, reach_voxels an int in [0, 3], keep_fraction "
                                  "in [0, 1], unexplained_margin and near_cabinet_m >= 0")


def carry_labels(previous: PointCloud, points: NDArray[np.float64], colours: NDArray[np.int32],
                 grid: VoxelGrid, reach: int) -> NDArray[np.int32]:
    """Each of ``points`` (shape (N, 3) [m], colour words ``colours``, shape (N,)) labelled as
    the ``previous`` cloud's carried object point (:data:`_CARRIED` labels) in its voxel of
    ``grid`` when its colour fits; a block's or line's colour among the points left is then
    looked up in the voxels within ``reach`` per axis (nearer offsets first) — only blocks and
    lines move while tracking holds, so only they are followed; :data:`NO_OBJECT` elsewhere."""
    was = previous.labels
    keep = np.flatnonzero(_is_carried(was))
    volume = np.full(int(np.prod(grid.shape)), NO_OBJECT, dtype=np.int16)
    volume[grid.flat_voxels(previous.points[keep])] = was[keep]
    labels = np.full(len(points), NO_OBJECT, dtype=np.int32)
    flat = grid.flat_voxels(points)
    got = volume[flat]
    hit = np.flatnonzero(got >= 0)
    hit = hit[_fits(got[hit], colours[hit])]
    labels[hit] = got[hit]
    moves = keep[_WANTED[was[keep]] >= 0]  # blocks and lines
    if reach == 0 or len(moves) == 0:
        return labels
    moved = grid.world_to_voxel(previous.points[moves], clip=True)
    low, high = moved.min(axis=0) - reach, moved.max(axis=0) + reach
    follow = np.flatnonzero(np.isin(colours, np.unique(_WANTED[was[moves]])))
    follow = follow[labels[follow] == NO_OBJECT]
    near = np.stack(np.unravel_index(flat[follow], grid.shape), axis=1)  # their voxels
    inside = np.all((near >= low) & (near <= high), axis=1)
    follow, near = follow[inside], near[inside]
    offsets = sorted(np.ndindex(*(2 * reach + 1,) * 3),
                     key=lambda o: sum((c - reach) ** 2 for c in o))
    top = np.asarray(grid.shape) - 1
    for offset in offsets[1:]:
        if len(follow) == 0:
            break
        got = volume[_flat(np.clip(near + np.asarray(offset) - reach, 0, top), grid)]
        ok = (got >= 0) & (_WANTED[np.maximum(got, 0)] == colours[follow])
        labels[follow[ok]] = got[ok]
        follow, near = follow[~ok], near[~ok]  # the points still unlabelled
    return labels


def _flat(voxels: NDArray[np.int64], grid: VoxelGrid) -> NDArray[np.intp]:
    """Flat indices of voxel indices (shape (N, 3), inside ``grid``) into its C-ordered array."""
    return np.ravel_multi_index(tuple(voxels.T), grid.shape)


def _is_carried(labels: NDArray[np.integer]) -> NDArray[np.bool_]:
    """Whether each label (shape (N,); -1: none) is one that is carried (:data:`_CARRIED`)."""
    return (labels >= 0) & (_WANTED[np.maximum(labels, 0)] != _NOT_CARRIED)


def _fits(labels: NDArray[np.integer], colours: NDArray[np.int32]) -> NDArray[np.bool_]:
    """Whether each point's colour word fits its carried label (both shape (N,), labels of
    :data:`_CARRIED`)."""
    wanted = _WANTED[labels]
    return np.where(wanted == _ANY_HUE, colours != GRAY, wanted == colours)


def _carry_or_copy(was: PointCloud, now: PointCloud, kept: list[int], grid: VoxelGrid,
                   reach: int) -> NDArray[np.int32]:
    """:func:`carry_labels` of ``now`` from ``was``; the points of the cameras in ``kept``
    (whose frame is the one ``was`` was made of: the same points in the same order) copy their
    carried labels instead."""
    labels = np.full(len(now), NO_OBJECT, dtype=np.int32)
    todo = np.ones(len(now), dtype=bool)
    for k in kept:
        there, here = was.camera == k, now.camera == k
        if np.count_nonzero(there) == np.count_nonzero(here):
            old = was.labels[there]
            labels[here] = np.where(_is_carried(old), old, NO_OBJECT)
            todo &= ~here
    if todo.all():
        return carry_labels(was, now.points, now.labels, grid, reach)
    rest = np.flatnonzero(todo)
    labels[rest] = carry_labels(was, now.points[rest], now.labels[rest], grid, reach)
    return labels


def track_labels(obs: Observation, grid: VoxelGrid, previous: PixelLabels,
                 config: LabelTrackingConfig, baseline_unexplained: int,
                 views: ViewClouds | None = None) -> PixelLabels | None:
    """The labelled cloud of ``obs`` carried from ``previous`` (see the module docs), or None
    when tracking gives up. ``baseline_unexplained``: :attr:`PixelLabels.unexplained` of the
    last full detection; ``views`` as :func:`~voxposer.perception.pixel_labels.colour_cloud`."""
    ee = np.asarray(obs.ee_position, np.float64)
    was = previous.cloud
    cabinet = np.isin(was.labels, np.fromiter(_CABINET, dtype=np.int32))
    if cabinet.any() and float(np.min(np.linalg.norm(was.points[cabinet] - ee, axis=1))) \
            < config.near_cabinet_m:
        return None
    kept = [k for k, view in enumerate(obs.cameras)
            if views is not None and k in views and views[k][0] is view]
    colour_pts = colour_cloud(obs, grid, views)
    points, colours = colour_pts.points, colour_pts.labels
    labels = _carry_or_copy(was, colour_pts, kept, grid, config.reach_voxels)
    gray = np.flatnonzero((labels != NO_OBJECT) & (colours == GRAY))
    if gripper_mask(points[gray], ee, np.asarray(obs.ee_quat, np.float64)).any():
        return None  # a gray object among the gray gripper's points: only detection parts them
    counts_was = np.bincount(was.labels[was.labels >= 0], minlength=len(catalog.OBJECTS))
    counts_now = np.bincount(labels[labels >= 0], minlength=len(catalog.OBJECTS))
    for k in _CARRIED:
        if counts_was[k] and counts_now[k] < config.keep_fraction * counts_was[k]:
            return None
    seen = [catalog.OBJECTS[k].name for k in _CARRIED if counts_now[k]]
    moving = {catalog.OBJECTS[k].name: np.flatnonzero(labels == k)  # blocks and lines
              for k in _CARRIED if counts_now[k] and _CARRIED[k] >= 0}
    tracks = {**previous.tracks, **object_tracks(points, moving)}
    out = finish_labels(colour_pts, labels, seen, obs, dict(previous.openings),
                        previous.cabinet, tracks)
    if out.unexplained > baseline_unexplained + config.unexplained_margin:
        return None
    return out


__all__ = ["LabelTrackingConfig", "carry_labels", "track_labels"]
