"""Checkpoints keep config, grid shape and vocabulary, and refuse another grid or vocabulary."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.unet.conftest import GRID
from voxposer.errors import ConfigError
from voxposer.unet._torch import torch
from voxposer.unet.checkpoint import load_checkpoint, save_checkpoint
from voxposer.unet.model import UNetConfig
from voxposer.unet.train import make_model
from voxposer.unet.vocabulary import Vocabulary


@pytest.fixture
def saved(tmp_path: Path, vocabulary: Vocabulary) -> Path:
    config = UNetConfig(base_channels=4, depth=1, embed_dim=4)
    model = make_model(config, vocabulary, GRID, np.random.default_rng(0))
    return save_checkpoint(tmp_path / "m.pt", model, vocabulary, GRID, 3.0, {"epoch": 2})


def test_round_trip_predicts_the_same(saved: Path, vocabulary: Vocabulary) -> None:
    ckpt = load_checkpoint(saved, grid_shape=GRID, vocabulary=vocabulary)
    again = load_checkpoint(saved)
    assert ckpt.grid_shape == GRID and ckpt.cost_scale == 3.0 and ckpt.meta["epoch"] == 2
    assert ckpt.vocabulary == vocabulary and ckpt.config.base_channels == 4
    obs = torch.rand(1, 4, GRID[0], GRID[1], generator=torch.Generator().manual_seed(0))
    tokens = torch.from_numpy(vocabulary.batch(["move to the red block"]))
    with torch.no_grad():
        assert torch.equal(ckpt.model(obs, tokens), again.model(obs, tokens))


def test_another_grid_is_refused_naming_both_shapes(saved: Path) -> None:
    with pytest.raises(ConfigError) as err:
        load_checkpoint(saved, grid_shape=(50, 50, 50))
    assert "(12, 12, 8)" in str(err.value) and "(50, 50, 50)" in str(err.value)


def test_another_vocabulary_is_refused_naming_both_shapes(saved: Path) -> None:
    other = Vocabulary.build(["push the blue block"])
    with pytest.raises(ConfigError) as err:
        load_checkpoint(saved, vocabulary=other)
    assert "(8,)" in str(err.value) and f"({len(other)},)" in str(err.value)


def test_a_missing_checkpoint_is_a_config_error(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="no U-Net checkpoint"):
        load_checkpoint(tmp_path / "none.pt")
