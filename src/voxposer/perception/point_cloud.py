"""Fusing RGB-D views into one labelled world-frame point cloud with normals.

Each camera's depth image is back-projected with its intrinsics K and camera-to-world extrinsics
(OpenCV axes: x right, y down, z forward). Normals come from the organised point map: at every
pixel the horizontal and vertical tangents are taken toward the neighbour with the smaller depth
jump (so edges keep good normals), crossed, and turned to face the camera.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid

#: A tangent whose depth jump exceeds this [m] crosses an edge; the normal there is left at 0.
EDGE_JUMP = 0.02


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


def _tangent(comp: tuple[NDArray[np.float32], ...], z: NDArray[np.float32], axis: int
             ) -> tuple[tuple[NDArray[np.float32], ...], NDArray[np.bool_]]:
    """Tangent along image ``axis`` toward the neighbour with the smaller depth jump."""
    lo = (slice(None), slice(None, -1)) if axis == 1 else (slice(None, -1), slice(None))
    hi = (slice(None), slice(1, None)) if axis == 1 else (slice(1, None), slice(None))
    jump = np.abs(z[hi] - z[lo])
    jf = np.full(z.shape, np.inf, dtype=np.float32)  # jump to the next pixel
    jb = np.full(z.shape, np.inf, dtype=np.float32)  # jump to the previous pixel
    jf[lo] = jump
    jb[hi] = jump
    use_bwd = jb < jf
    out = []
    for c in comp:
        t = np.zeros(z.shape, dtype=np.float32)
        t[lo] = c[hi] - c[lo]  # forward difference, stored at the lower pixel
        t[hi] = np.where(use_bwd[hi], c[hi] - c[lo], t[hi])
        out.append(t)
    ok = np.minimum(jf, jb) < EDGE_JUMP
    return tuple(out), ok


def _camera_normals(x: NDArray[np.float32], y: NDArray[np.float32], z: NDArray[np.float32]
                    ) -> tuple[NDArray[np.float32], NDArray[np.bool_]]:
    """Camera-frame unit normals, shape (H, W, 3), facing the camera, and where they are valid."""
    finite = np.isfinite(z)
    zf = np.where(finite, z, np.float32(1e6))
    comp = (np.where(finite, x, 0), np.where(finite, y, 0), zf)
    (ux, uy, uz), ok_u = _tangent(comp, zf, axis=1)
    (vx, vy, vz), ok_v = _tangent(comp, zf, axis=0)
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    norm = np.sqrt(nx * nx + ny * ny + nz * nz)
    ok = ok_u & ok_v & finite & (norm > 1e-12)
    scale = np.where(ok, 1.0 / np.maximum(norm, 1e-12), 0.0).astype(np.float32)
    # The camera sits at the origin: flip normals that point away from it.
    flip = np.where(nx * comp[0] + ny * comp[1] + nz * zf > 0, -scale, scale)
    return np.stack([nx * flip, ny * flip, nz * flip], axis=-1), ok


def camera_normals(depth: NDArray[np.float32], intrinsics: NDArray[np.float64]
                   ) -> NDArray[np.float32]:
    """Unit normals in the camera frame, shape (H, W, 3), of a depth image [m], shape (H, W).

    They face the camera; rows are zero where no normal can be estimated (background, pixels
    with no neighbour on the same surface).
    """
    x, y, z = _camera_points(depth, intrinsics)
    return _camera_normals(x, y, z)[0]


def fuse_views(views: Sequence[DepthView], grid: VoxelGrid | None = None) -> PointCloud:
    """One world-frame cloud from several RGB-D views, cropped to ``grid``'s box when given.

    Background pixels (infinite depth) are dropped.
    """
    parts: list[PointCloud] = []
    for cam_index, view in enumerate(views):
        x, y, z = _camera_points(view.depth, view.intrinsics)
        normals_cam, _ = _camera_normals(x, y, z)
        idx = np.flatnonzero(np.isfinite(z))
        rot, trans = view.extrinsics[:3, :3], view.extrinsics[:3, 3]
        xk, yk, zk = (c.ravel()[idx].astype(np.float64) for c in (x, y, z))
        coords = [rot[i, 0] * xk + rot[i, 1] * yk + rot[i, 2] * zk + trans[i] for i in range(3)]
        if grid is not None:  # crop one axis at a time (cheaper than an (N, 3) mask)
            inside = np.ones(len(idx), dtype=bool)
            for i in range(3):
                inside &= (coords[i] >= grid.bounds_min[i]) & (coords[i] <= grid.bounds_max[i])
            idx, coords = idx[inside], [c[inside] for c in coords]
        pts = np.stack(coords, axis=1)
        nk = normals_cam.reshape(-1, 3)[idx]
        normals = nk.astype(np.float64) @ rot.T
        labels = view.object_ids.ravel()[idx].astype(np.int32)
        colors = view.rgb.reshape(-1, 3)[idx]
        parts.append(PointCloud(pts, normals, labels, colors,
                                np.full(len(pts), cam_index, dtype=np.int16)))
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
