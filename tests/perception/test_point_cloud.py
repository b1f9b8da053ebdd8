"""Back-projection and normals on a synthetic depth image of a plane (no simulator)."""

from types import SimpleNamespace

import numpy as np

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception import backproject, camera_normals, fuse_views

K = np.array([[100.0, 0.0, 31.5], [0.0, 100.0, 23.5], [0.0, 0.0, 1.0]])


def _looking_down(height: float) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = np.diag([1.0, -1.0, -1.0])  # camera z (forward) = world −z
    pose[:3, 3] = (0.0, 0.0, height)
    return pose


def test_flat_floor_backprojects_to_z0_with_up_normals() -> None:
    depth = np.full((48, 64), 1.0, dtype=np.float32)
    pts = backproject(depth, K, _looking_down(1.0))
    np.testing.assert_allclose(pts[..., 2], 0.0, atol=1e-6)
    np.testing.assert_allclose(pts[23, 31:33, :2].mean(axis=0), 0.0, atol=0.006)
    normals = camera_normals(depth, K)
    np.testing.assert_allclose(normals[..., 2], -1.0, atol=1e-6)  # toward the camera


def test_fuse_crops_and_labels() -> None:
    depth = np.full((48, 64), 1.0, dtype=np.float32)
    depth[:5] = np.inf
    view = SimpleNamespace(depth=depth, intrinsics=K, extrinsics=_looking_down(1.0),
                           object_ids=np.full((48, 64), 3, np.int32),
                           rgb=np.zeros((48, 64, 3), np.uint8))
    grid = VoxelGrid((-0.1, -0.5, -0.1), (0.5, 0.5, 0.5), (10, 10, 10))
    cloud = fuse_views([view], grid)
    assert len(cloud) > 0 and np.all(cloud.points[:, 0] >= -0.1)
    assert np.all(cloud.labels == 3) and np.all(cloud.camera == 0)
    np.testing.assert_allclose(cloud.normals[:, 2], 1.0, atol=1e-6)  # world up
