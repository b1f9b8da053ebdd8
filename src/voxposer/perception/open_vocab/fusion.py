"""Multi-view fusion: per-camera masks → 3-D object instances → one labelled point cloud.

Each camera's masks are lifted to world points with its depth, intrinsics and extrinsics
(:func:`voxposer.perception.point_cloud.backproject`). Masks of one query seen by different
cameras are one instance when their points share voxels of a coarsened workspace grid (two
cameras see different faces of an object, so they overlap in a band, not everywhere). Instances
are named after their query, then "block 2", "block 3"…; an instance near (in 3-D) one of a
previous set keeps its name, so names follow objects from one detection to the next.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.observation import CameraFrame
from voxposer.perception.point_cloud import PointCloud, backproject, fuse_views

#: Views of one query are one object when this fraction of the smaller's voxels are shared.
MIN_OVERLAP = 0.2
#: Voxels of the association grid are this many workspace voxels on a side.
COARSEN = 2
#: A new instance within this distance [m] of a previous one of the same query keeps its name.
MAX_MATCH_M = 0.1


@dataclass(frozen=True, eq=False)
class ViewMask:
    """One object's mask in one camera.

    Attributes:
        camera: index of the camera in the observation's ``cameras``.
        query: index of the text query it answers.
        mask: its pixels, shape (H, W), bool.
        score: the detector's confidence in [0, 1] (kept while tracked).
        motion: how far its box centre moved in the last tracking step [px], shape (2,)
            (x, y); zeros when just detected.
    """

    camera: int
    query: int
    mask: NDArray[np.bool_]
    score: float
    motion: NDArray[np.float64] = dataclasses.field(default_factory=lambda: np.zeros(2))


@dataclass(frozen=True, eq=False)
class Instance:
    """One object in 3-D: the masks of every camera that sees it.

    Attributes:
        name: its name: the query, or the query and a number ("block 2").
        query: index of the text query it answers.
        views: its masks in the cameras that see it.
        centroid: mean of its world points [m], shape (3,).
    """

    name: str
    query: int
    views: tuple[ViewMask, ...]
    centroid: NDArray[np.float64]

    @property
    def score(self) -> float:
        """The best confidence among its views."""
        return max(v.score for v in self.views)


def world_points(frames: Sequence[CameraFrame]) -> list[NDArray[np.float64]]:
    """Per camera, the world point [m] of every pixel, shape (H, W, 3) (NaN for no depth)."""
    return [backproject(f.depth, f.intrinsics, f.extrinsics) for f in frames]


def in_workspace(points: NDArray[np.float64], grid: VoxelGrid) -> NDArray[np.bool_]:
    """Which pixels of a camera's per-pixel points (shape (H, W, 3)) have a finite point inside
    the workspace, shape (H, W)."""
    with np.errstate(invalid="ignore"):
        return np.all((points >= grid.bounds_min) & (points <= grid.bounds_max), axis=-1)


def mask_points(points: NDArray[np.float64], mask: NDArray[np.bool_], grid: VoxelGrid,
                inside: NDArray[np.bool_] | None = None) -> NDArray[np.float64]:
    """The finite in-workspace world points [m], shape (N, 3), of a mask (shape (H, W)) over a
    camera's per-pixel points (shape (H, W, 3)); ``inside``: :func:`in_workspace` of them when
    already computed."""
    return points[mask & (inside if inside is not None else in_workspace(points, grid))]


def _voxels(pts: NDArray[np.float64], grid: VoxelGrid) -> NDArray[np.int64]:
    """Sorted flat indices of the association grid's voxels holding ``pts`` (shape (N, 3))."""
    coarse = grid.coarsen(COARSEN)
    return np.unique(np.ravel_multi_index(coarse.world_to_voxel(pts, clip=True).T, coarse.shape))


def _groups(masks: Sequence[ViewMask], voxels: Sequence[NDArray[np.int64]]) -> list[list[int]]:
    """Masks (indices) grouped into objects: one query, other cameras, shared voxels."""
    parent = list(range(len(masks)))

    def root(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    for i in range(len(masks)):
        for j in range(i + 1, len(masks)):
            a, b = masks[i], masks[j]
            if a.query != b.query or a.camera == b.camera:
                continue
            shared = len(np.intersect1d(voxels[i], voxels[j], assume_unique=True))
            if shared >= MIN_OVERLAP * min(len(voxels[i]), len(voxels[j])):
                parent[root(j)] = root(i)
    groups: dict[int, list[int]] = {}
    for k in range(len(masks)):
        groups.setdefault(root(k), []).append(k)
    return list(groups.values())


def instance_name(query: str, number: int) -> str:
    """The name of the ``number``-th (from 1) instance of ``query``: "block", "block 2"…"""
    return query if number == 1 else f"{query} {number}"


def _names(found: list[Instance], queries: Sequence[str], previous: Sequence[Instance]
           ) -> list[Instance]:
    """``found`` renamed: near a previous instance of their query, its name; otherwise the
    first free "query N", the most confident first."""
    names: dict[int, str] = {}
    pairs = sorted((float(np.linalg.norm(f.centroid - p.centroid)), i, p.name)
                   for i, f in enumerate(found) for p in previous if p.query == f.query)
    for dist, i, name in pairs:
        if dist <= MAX_MATCH_M and i not in names and name not in names.values():
            names[i] = name
    for i in sorted(range(len(found)), key=lambda k: -found[k].score):
        if i in names:
            continue
        number = 1
        while instance_name(queries[found[i].query], number) in names.values():
            number += 1
        names[i] = instance_name(queries[found[i].query], number)
    return [dataclasses.replace(f, name=names[i]) for i, f in enumerate(found)]


def fuse_masks(frames: Sequence[CameraFrame], masks: Sequence[ViewMask], grid: VoxelGrid,
               queries: Sequence[str], previous: Sequence[Instance] = (),
               points: Sequence[NDArray[np.float64]] | None = None) -> tuple[Instance, ...]:
    """The 3-D instances seen in ``masks`` of the views ``frames``, best first.

    Args:
        frames: the views the masks were taken in.
        masks: per-camera masks (``camera`` indexes ``frames``); masks with no point inside
            the workspace are dropped.
        grid: the workspace grid.
        queries: the text queries (names of the instances).
        previous: instances of an earlier detection whose names are kept (matched in 3-D).
        points: :func:`world_points` of ``frames`` when already computed.
    """
    pts = list(points) if points is not None else world_points(frames)
    inside = [in_workspace(p, grid) for p in pts]
    lifted = [mask_points(pts[m.camera], m.mask, grid, inside[m.camera]) for m in masks]
    keep = [k for k, p in enumerate(lifted) if len(p)]
    kept = [masks[k] for k in keep]
    groups = _groups(kept, [_voxels(lifted[k], grid) for k in keep])
    found = [Instance(name="", query=kept[g[0]].query, views=tuple(kept[k] for k in g),
                      centroid=np.concatenate([lifted[keep[k]] for k in g]).mean(axis=0))
             for g in groups]
    named = _names(found, queries, previous)
    return tuple(sorted(named, key=lambda inst: -inst.score))


def labelled_cloud(frames: Sequence[CameraFrame], instances: Sequence[Instance],
                   grid: VoxelGrid) -> PointCloud:
    """The fused workspace cloud of ``frames``, each point labelled with the index of the
    instance whose mask holds its pixel (-1: none; where masks overlap, the more confident
    instance's)."""
    labelled = []
    for cam, frame in enumerate(frames):
        ids = np.full(frame.depth.shape, -1, dtype=np.int32)
        for k in sorted(range(len(instances)), key=lambda i: instances[i].score):
            for view in instances[k].views:
                if view.camera == cam:
                    ids[view.mask] = k
        labelled.append(dataclasses.replace(frame, object_ids=ids))
    return fuse_views(labelled, grid)
