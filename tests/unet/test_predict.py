"""The predictor returns the planner's CostMap type on the planning grid, with the U-Net's cost
and its target where that cost is lowest."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.unet.conftest import GRID, tiny_samples
from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.unet._torch import torch
from voxposer.unet.checkpoint import load_checkpoint, save_checkpoint
from voxposer.unet.encoding import ObservationVoxels
from voxposer.unet.model import UNetConfig
from voxposer.unet.predict import predict_cost_map
from voxposer.unet.train import batch_from_arrays, make_model, train_step
from voxposer.unet.vocabulary import Vocabulary
from voxposer.valuemaps.cost import CostMap

#: a workspace whose planning grid (downsample 2) is the tiny dataset's grid
FINE = VoxelGrid([0, 0, 0], [0.6, 0.6, 0.4], tuple(2 * n for n in GRID))


@pytest.fixture
def trained(tmp_path: Path, vocabulary: Vocabulary) -> Path:
    samples = tiny_samples()
    config = UNetConfig(base_channels=8, depth=2, embed_dim=8)
    model = make_model(config, vocabulary, GRID, np.random.default_rng(0))
    batch = batch_from_arrays(samples["occupancy"], samples["colour"], samples["cost"],
                              samples["instruction"], vocabulary, config, 3.0)
    optimiser = torch.optim.Adam(model.parameters(), lr=1e-2)
    for _ in range(60):
        train_step(model, optimiser, batch)
    return save_checkpoint(tmp_path / "m.pt", model, vocabulary, GRID, 3.0)


def test_prediction_is_a_planner_cost_map(trained: Path) -> None:
    samples = tiny_samples()
    obs = ObservationVoxels(samples["occupancy"][0], samples["colour"][0])
    cmap = predict_cost_map(trained, obs, samples["instruction"][0], grid=FINE,
                            start=[0.05, 0.05, 0.3])
    assert isinstance(cmap, CostMap)
    assert cmap.grid.shape == GRID and cmap.cost.shape == GRID and cmap.cost.dtype == np.float32
    assert cmap.target_mask[np.unravel_index(cmap.cost.argmin(), GRID)]
    assert not cmap.obstacles[cmap.target_mask].any()
    true_min = np.unravel_index(samples["cost"][0].argmin(), GRID)
    pred_min = np.unravel_index(cmap.cost.argmin(), GRID)
    assert np.linalg.norm(np.subtract(true_min, pred_min)) <= 3.0  # voxels


def test_another_planning_grid_is_refused_naming_both_shapes(trained: Path) -> None:
    samples = tiny_samples()
    obs = ObservationVoxels(samples["occupancy"][0], samples["colour"][0])
    other = VoxelGrid([0, 0, 0], [1, 1, 1], (100, 100, 100))
    with pytest.raises(ConfigError) as err:
        predict_cost_map(trained, obs, "move to the red block", grid=other, start=[0.5, 0.5, 0.5])
    assert "(12, 12, 8)" in str(err.value) and "(50, 50, 50)" in str(err.value)
    assert load_checkpoint(trained).grid_shape == GRID
