"""Object labels for a fused cloud from RGB and depth alone (no segmentation channel).

Each view's pixels get a colour word (:func:`~voxposer.perception.colour_names.colour_labels`);
the views are fused into one world cloud carrying those colour words; then, in order:

1. coloured blocks and lines: 3-D clusters per colour word, told apart by shape
   (:mod:`voxposer.perception.colour_objects`);
2. the cabinet, its drawers and handles: a fit to depth in the fixture's box
   (:mod:`voxposer.perception.cabinet_fit`), among the points with some hue;
3. the table: what is left at table height with some hue;
4. the robot: what is left and achromatic; of it, the gripper is what lies around the end
   effector's pose (the robot's own joint state, not the simulator's).

Labels are catalog labels (:data:`voxposer.catalog.OBJECTS` indices), as with ground truth, so
detection and obstacle maps work on either cloud alike.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Final

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from voxposer.catalog import NO_OBJECT, label_of
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.cabinet_fit import fit_cabinet
from voxposer.perception.colour_names import GRAY, colour_labels
from voxposer.perception.colour_objects import find_blocks_and_lines, line_prior
from voxposer.perception.observation import CameraFrame, Observation
from voxposer.perception.point_cloud import PointCloud, concatenate_clouds, fuse_views

#: Points at most this high [m] (and down the table's edge) with some hue, left over once blocks,
#: lines and the cabinet are found, are the table. The band holds a consumer RGB-D camera's table
#: points: depth noise σ ≈ 4 mm at 1.2 m and a 0.5° calibration tilt (~1 cm across the table;
#: :mod:`voxposer.perception.sensor_noise`); nothing else lies that low but the flat lines.
TABLE_TOP_M: Final = 0.02
#: The gripper: robot points from this far behind the end effector along its approach axis
#: to this far beyond it [m] …
GRIPPER_BEHIND_M: Final = 0.12
GRIPPER_BEYOND_M: Final = 0.02
#: … and at most this far from that axis [m].
GRIPPER_RADIUS_M: Final = 0.11


@dataclass(frozen=True)
class PixelLabels:
    """The labelled cloud of one observation.

    Attributes:
        cloud: fused, grid-cropped world cloud; ``labels`` are catalog labels (-1: none).
        seen: names of the objects found (each with at least one point).
        openings: drawer ("top", …) → measured opening [m] (drawers whose front was seen, or
            known from before).
        cabinet: whether the cabinet was found.
        tracks: the tracks of the blocks and lines found, to find them again next time
            (the gray block and line among other gray points): block name → its centre [m],
            shape (3,); line name → its footprint
            (:func:`~voxposer.perception.colour_objects.line_prior`).
        unexplained: points with a chromatic colour word that no block, line or cabinet part
            took (the table's own, stray pixels; the tracker's baseline,
            :mod:`voxposer.perception.label_tracking`).
    """

    cloud: PointCloud
    seen: tuple[str, ...]
    openings: dict[str, float]
    cabinet: bool
    tracks: dict[str, NDArray[np.float64]] = field(default_factory=dict)
    unexplained: int = 0


#: Per camera index: (the view, its grid-cropped points with their colour words) — what
#: :func:`colour_cloud` keeps between calls when given a dict to keep it in.
ViewClouds = dict[int, tuple[CameraFrame, PointCloud]]


def colour_cloud(obs: Observation, grid: VoxelGrid, reuse: ViewClouds | None = None
                 ) -> PointCloud:
    """Every view fused into one cloud cropped to ``grid``, whose ``labels`` are colour words
    (indices into :data:`voxposer.catalog.COLOR_NAMES`, -1 none) read from RGB. The views'
    segmentation channel is never read: the fused cloud's labels are replaced by the colour
    words of its points' RGB (only the pixels kept by the crop are classified).

    ``reuse`` keeps each view's coloured points between calls (updated in place): a view that
    is the very frame seen last time (a camera whose next frame is not due) is neither lifted
    nor classified again; the cloud is the same as without it."""
    parts: list[PointCloud] = []
    for k, view in enumerate(obs.cameras):
        held = None if reuse is None else reuse.get(k)
        if held is not None and held[0] is view:
            parts.append(held[1])
            continue
        blank = replace(view, object_ids=np.full(view.depth.shape, -1, dtype=np.int32))
        part = fuse_views([blank], grid)
        part = replace(part, labels=colour_labels(part.colors),
                       camera=np.full(len(part), k, dtype=np.int16))
        parts.append(part)
        if reuse is not None:
            reuse[k] = (view, part)
    return concatenate_clouds(parts)


def gripper_mask(points: NDArray[np.float64], ee_position: NDArray[np.float64],
                  ee_quat: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Points (shape (N, 3)) inside the gripper's cylinder around the end-effector pose."""
    approach = Rotation.from_quat(ee_quat).apply([0.0, 0.0, 1.0])
    rel = points - ee_position
    along = rel @ approach
    radial = np.linalg.norm(rel - along[:, None] * approach, axis=1)
    return (along >= -GRIPPER_BEHIND_M) & (along <= GRIPPER_BEYOND_M) & (radial <= GRIPPER_RADIUS_M)


def label_pixels(obs: Observation, grid: VoxelGrid,
                 prior_openings: dict[str, float] | None = None,
                 prior_tracks: dict[str, NDArray[np.float64]] | None = None,
                 views: ViewClouds | None = None) -> PixelLabels:
    """Catalog labels for the fused cloud of ``obs`` from its RGB and depth only.

    Args:
        obs: the observation (its ``object_ids`` are not read).
        grid: workspace grid the cloud is cropped to.
        prior_openings: drawer openings [m] measured before, for drawers hidden now.
        prior_tracks: tracks of the blocks and lines found before
            (:attr:`PixelLabels.tracks`), to follow the gray block and line when they join
            other gray points (:mod:`voxposer.perception.colour_objects`).
        views: each view's coloured points kept between calls (:func:`colour_cloud`).
    """
    colour_pts = colour_cloud(obs, grid, views)
    points, colours = colour_pts.points, colour_pts.labels
    labels = np.full(len(points), NO_OBJECT, dtype=np.int32)
    seen: list[str] = []
    found = find_blocks_and_lines(points, colours, prior_tracks)
    for name, idx in found.items():
        labels[idx] = label_of(name)
        seen.append(name)
    hued = np.flatnonzero((labels == NO_OBJECT) & (colours != GRAY))
    fit = fit_cabinet(points[hued], colour_pts.normals[hued], prior_openings)
    for name, idx in fit.parts.items():
        if len(idx):
            labels[hued[idx]] = label_of(name)
            seen.append(name)
    return finish_labels(colour_pts, labels, seen, obs, dict(fit.openings), fit.present,
                         object_tracks(points, found))


def object_tracks(points: NDArray[np.float64], found: dict[str, NDArray[np.int64]]
                  ) -> dict[str, NDArray[np.float64]]:
    """:attr:`PixelLabels.tracks` of the blocks and lines ``found`` (name → indices into
    ``points``, shape (N, 3) [m])."""
    tracks: dict[str, NDArray[np.float64]] = {}
    for name, idx in found.items():
        if name.endswith(" block"):
            tracks[name] = points[idx].mean(axis=0)
        elif name.endswith(" line") and len(idx) >= 2:
            tracks[name] = line_prior(points[idx])
    return tracks


def finish_labels(colour_pts: PointCloud, labels: NDArray[np.int32], seen: list[str],
                  obs: Observation, openings: dict[str, float], cabinet: bool,
                  tracks: dict[str, NDArray[np.float64]]) -> PixelLabels:
    """The labelled cloud once blocks, lines and cabinet parts hold their labels (``labels``,
    shape (N,), updated in place): what is left at table height with some hue is the table,
    what is left achromatic the robot, and of it what lies around the end effector's pose the
    gripper."""
    points, colours = colour_pts.points, colour_pts.labels
    free = labels == NO_OBJECT
    achromatic = colours == GRAY
    unexplained = int(np.count_nonzero(free & (colours >= 0) & ~achromatic))
    labels[free & ~achromatic & (points[:, 2] <= TABLE_TOP_M)] = label_of("table")
    robot = np.flatnonzero(free & achromatic)
    gripper = robot[gripper_mask(points[robot], np.asarray(obs.ee_position, np.float64),
                                 np.asarray(obs.ee_quat, np.float64))]
    labels[robot] = label_of("robot")
    labels[gripper] = label_of("gripper")
    seen = seen + [n for n in ("table", "robot", "gripper") if np.any(labels == label_of(n))]
    cloud = PointCloud(points, colour_pts.normals, labels, colour_pts.colors, colour_pts.camera)
    return PixelLabels(cloud, tuple(seen), openings, cabinet, tracks, unexplained)


__all__ = ["PixelLabels", "ViewClouds", "colour_cloud", "finish_labels", "gripper_mask",
           "label_pixels", "object_tracks"]
