"""Normals of an organised point map: faces the camera, keeps edges, none where depth is missing."""

import numpy as np

from voxposer.perception import camera_normals

K = np.array([[100.0, 0.0, 31.5], [0.0, 100.0, 23.5], [0.0, 0.0, 1.0]])


def test_a_tilted_plane_has_one_normal_facing_the_camera() -> None:
    # the plane z = 1 + 0.5 x (camera frame): depth d with d = 1 + 0.5 * u * d
    u = (np.arange(64) - K[0, 2]) / K[0, 0]
    depth = np.tile((1.0 / (1.0 - 0.5 * u)).astype(np.float32), (48, 1))
    normals = camera_normals(depth, K)
    expected = np.array([0.5, 0.0, -1.0]) / np.linalg.norm([0.5, 0.0, -1.0])
    np.testing.assert_allclose(normals.reshape(-1, 3), np.tile(expected, (48 * 64, 1)),
                               atol=1e-4)


def test_a_step_keeps_both_surfaces_normals_and_none_where_depth_is_missing() -> None:
    depth = np.full((48, 64), 1.0, dtype=np.float32)
    depth[:, 32:] = 0.8  # a raised block: a 20 cm jump between columns 31 and 32
    depth[10, 10] = np.inf
    normals = camera_normals(depth, K)
    for col in (31, 32):  # either side of the step takes its tangent along its own surface
        np.testing.assert_allclose(normals[20, col], [0.0, 0.0, -1.0], atol=1e-6)
    assert not normals[10, 10].any()  # no depth, no normal
    np.testing.assert_allclose(normals[10, 9], [0.0, 0.0, -1.0], atol=1e-6)  # its neighbour


def test_an_isolated_pixel_has_no_normal() -> None:
    depth = np.full((48, 64), np.inf, dtype=np.float32)
    depth[20, 20] = 1.0
    assert not camera_normals(depth, K).any()
