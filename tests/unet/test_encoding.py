"""The observation at the cost grid: voxelised colour means and the 2.5D top-down encoding."""

from __future__ import annotations

import numpy as np
import pytest

from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.unet.encoding import cost_to_target, encode, target_to_cost, voxelise


def test_voxelise_averages_colours_and_drops_points_outside() -> None:
    grid = VoxelGrid([0, 0, 0], [1, 1, 1], (4, 4, 4))
    points = [[0.1, 0.1, 0.1], [0.2, 0.2, 0.2], [0.9, 0.9, 0.6], [1.5, 0.5, 0.5]]
    colours = [[100, 0, 0], [200, 50, 0], [0, 0, 255], [255, 255, 255]]
    obs = voxelise(points, colours, grid)
    assert obs.occupancy.sum() == 2
    np.testing.assert_array_equal(obs.colour[0, 0, 0], [150, 25, 0])
    np.testing.assert_array_equal(obs.colour[3, 3, 2], [0, 0, 255])


def test_topdown_keeps_the_highest_voxel_of_each_column() -> None:
    occ = np.zeros((1, 2, 2, 4), dtype=np.uint8)
    colour = np.zeros((1, 2, 2, 4, 3), dtype=np.uint8)
    occ[0, 0, 0, [0, 2]] = 1
    colour[0, 0, 0, 0] = (255, 0, 0)
    colour[0, 0, 0, 2] = (0, 255, 0)
    enc = encode(occ, colour, "topdown")
    assert enc.shape == (1, 4, 2, 2)
    assert enc[0, 0, 0, 0] == pytest.approx(3 / 4)  # top voxel k = 2 of Z = 4
    np.testing.assert_allclose(enc[0, 1:, 0, 0], [0, 1, 0])
    assert not enc[0, :, 1, 1].any()  # an empty column is all zeros
    assert encode(occ, colour, "voxel").shape == (1, 4, 2, 2, 4)


@pytest.mark.parametrize("encoding", ["topdown", "voxel"])
def test_target_layout_round_trips(encoding: str) -> None:
    cost = np.random.default_rng(0).random((2, 3, 4, 5)).astype(np.float32)
    back = target_to_cost(cost_to_target(cost, encoding), encoding)  # type: ignore[arg-type]
    np.testing.assert_array_equal(back, cost)


def test_unknown_encoding_lists_the_known_ones() -> None:
    with pytest.raises(ConfigError, match="encodings are: voxel, topdown"):
        encode(np.zeros((1, 1, 1, 1)), np.zeros((1, 1, 1, 1, 3)), "rgbd")  # type: ignore[arg-type]
