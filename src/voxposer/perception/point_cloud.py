"""Fusing RGB-D views into one labelled world-frame point cloud with normals.

Each camera's depth image is back-projected with its intrinsics K and camera-to-world extrinsics
(OpenCV axes: x right, y down, z forward). Normals come from the organised point map
(:mod:`voxposer.perception.normals`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numba
import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.normals import camera_frame_normals


class DepthView(Protocol):
    """What fusion needs of a camera view (e.g. :class:`voxposer.perception.observation.CameraFrame`)."""

    @property
    def depth(self) -> NDArray[np.float32]: ...
    @property
    def intrinsics(self) -> NDArray[np.float64]: ...
    @property
    def extrinsics(self) -> NDArray[np.float64]: ...
    @property
    def object_ids(self) -> NDArray[np.int32]: ...
    @property
    def rgb(self) -> NDArray[np.uint8]: ...


@dataclass(frozen=True)
class PointCloud:
    """A labelled point cloud in the world frame.

    Attributes:
        points: positions [m], shape (N, 3).
        normals: unit surface normals facing the observing camera, shape (N, 3); all-zero rows
            where no normal could be estimated (isolated pixels).
        labels: scene-object label of each point, shape (N,), int32 (-1: no object).
        colors: RGB of each point, shape (N, 3), uint8.
        camera: index of the camera that saw each point, shape (N,), int16.
    """

    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    labels: NDArray[np.int32]
    colors: NDArray[np.uint8]
    camera: NDArray[np.int16]

    def __len__(self) -> int:
        return int(self.points.shape[0])

    def select(self, mask: NDArray[np.bool_]) -> PointCloud:
        """The points where ``mask`` (shape (N,)) is True."""
        return PointCloud(self.points[mask], self.normals[mask], self.labels[mask],
                          self.colors[mask], self.camera[mask])


def _camera_points(depth: NDArray[np.float32], intrinsics: NDArray[np.float64]
                   ) -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32]]:
    """Camera-frame coordinates (x, y, z) [m], each shape (H, W); NaN where depth is not finite."""
    h, w = depth.shape
    k = intrinsics
    u = ((np.arange(w) - k[0, 2]) / k[0, 0]).astype(np.float32)
    v = ((np.arange(h) - k[1, 2]) / k[1, 1]).astype(np.float32)
    z = np.where(np.isfinite(depth), depth, np.float32(np.nan)).astype(np.float32)
    return u[None, :] * z, v[:, None] * z, z


def backproject(depth: NDArray[np.float32], intrinsics: NDArray[np.float64],
                extrinsics: NDArray[np.float64]) -> NDArray[np.float64]:
    """World points [m], shape (H, W, 3), of every pixel of a depth image [m], shape (H, W).

    Pixels with non-finite depth give NaN points.
    """
    x, y, z = _camera_points(depth, intrinsics)
    cam = np.stack([x, y, z], axis=-1).astype(np.float64)
    with np.errstate(invalid="ignore"):
        return cam @ extrinsics[:3, :3].T + extrinsics[:3, 3]


def camera_normals(depth: NDArray[np.float32], intrinsics: NDArray[np.float64]
                   ) -> NDArray[np.float32]:
    """Unit normals in the camera frame, shape (H, W, 3), of a depth image [m], shape (H, W).

    They face the camera; rows are zero where no normal can be estimated (background, pixels
    with no neighbour on the same surface).
    """
    x, y, z = _camera_points(depth, intrinsics)
    return camera_frame_normals(x, y, z)[0]


@numba.njit(cache=True, nogil=True)
def _to_world(x: np.ndarray, y: np.ndarray, z: np.ndarray, normals: np.ndarray,
              extrinsics: np.ndarray, lo: np.ndarray, hi: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """(flat pixel indices, world points [m] (K, 3), world normals (K, 3)) of the pixels with a
    depth whose point lies in the box [lo, hi] [m], in pixel order: one pass over the image."""
    h, w = z.shape
    idx = np.empty(h * w, dtype=np.int64)
    pts = np.empty((h * w, 3))
    nrm = np.empty((h * w, 3))
    k = 0
    for i in range(h):
        for j in range(w):
            if not np.isfinite(z[i, j]):
                continue
            cx, cy, cz = float(x[i, j]), float(y[i, j]), float(z[i, j])
            e = extrinsics
            px = e[0, 0] * cx + e[0, 1] * cy + e[0, 2] * cz + e[0, 3]
            py = e[1, 0] * cx + e[1, 1] * cy + e[1, 2] * cz + e[1, 3]
            pz = e[2, 0] * cx + e[2, 1] * cy + e[2, 2] * cz + e[2, 3]
            if not (lo[0] <= px <= hi[0] and lo[1] <= py <= hi[1] and lo[2] <= pz <= hi[2]):
                continue
            idx[k] = i * w + j
            pts[k, 0], pts[k, 1], pts[k, 2] = px, py, pz
            nx, ny, nz = normals[i, j, 0], normals[i, j, 1], normals[i, j, 2]
            for a in range(3):
                nrm[k, a] = e[a, 0] * nx + e[a, 1] * ny + e[a, 2] * nz
            k += 1
    return idx[:k].copy(), pts[:k].copy(), nrm[:k].copy()


def fuse_views(views: Sequence[DepthView], grid: VoxelGrid | None = None,
               reuse: dict[int, tuple[DepthView, PointCloud]] | None = None) -> PointCloud:
    """One world-frame cloud from several RGB-D views, cropped to ``grid``'s box when given.

    Background pixels (infinite depth) are dropped. ``reuse`` (camera index → (view, its
    points)) keeps each view's points between calls: a view that is the very object seen last
    time (a camera whose next frame is not due yet) is not back-projected again; the dict is
    updated in place.
    """
    parts: list[PointCloud] = []
    lo = np.full(3, -np.inf) if grid is None else np.asarray(grid.bounds_min, dtype=np.float64)
    hi = np.full(3, np.inf) if grid is None else np.asarray(grid.bounds_max, dtype=np.float64)
    for cam_index, view in enumerate(views):
        held = None if reuse is None else reuse.get(cam_index)
        if held is not None and held[0] is view:
            parts.append(held[1])
            continue
        x, y, z = _camera_points(view.depth, view.intrinsics)
        normals_cam, _ = camera_frame_normals(x, y, z)
        ext = np.ascontiguousarray(view.extrinsics, dtype=np.float64)
        idx, pts, normals = _to_world(x, y, z, normals_cam, ext, lo, hi)
        labels = view.object_ids.ravel()[idx].astype(np.int32)
        colors = view.rgb.reshape(-1, 3)[idx]
        parts.append(PointCloud(pts, normals, labels, colors,
                                np.full(len(pts), cam_index, dtype=np.int16)))
        if reuse is not None:
            reuse[cam_index] = (view, parts[-1])
    return concatenate_clouds(parts)


def concatenate_clouds(parts: Sequence[PointCloud]) -> PointCloud:
    """One cloud of ``parts``' points, in order (an empty cloud for none)."""
    if not parts:
        return PointCloud(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, np.int32),
                          np.zeros((0, 3), np.uint8), np.zeros(0, np.int16))
    return PointCloud(
        np.concatenate([p.points for p in parts]),
        np.concatenate([p.normals for p in parts]),
        np.concatenate([p.labels for p in parts]),
        np.concatenate([p.colors for p in parts]),
        np.concatenate([p.camera for p in parts]),
    )
