"""The FiLM U-Net learns: a tiny seeded model overfits a tiny dataset, and reads the instruction."""

from __future__ import annotations

import numpy as np
import pytest

from tests.unet.conftest import GRID, INSTRUCTIONS
from voxposer.errors import ConfigError
from voxposer.unet._torch import torch
from voxposer.unet.model import UNetConfig
from voxposer.unet.train import batch_from_arrays, make_model, train_step
from voxposer.unet.vocabulary import Vocabulary

STEPS = 40
FACTOR = 10.0


def _overfit(samples: dict, vocabulary: Vocabulary, encoding: str, seed: int = 0
             ) -> tuple[list[float], object, object]:
    config = UNetConfig(encoding=encoding, base_channels=8, depth=2, embed_dim=8)  # type: ignore[arg-type]
    model = make_model(config, vocabulary, GRID, np.random.default_rng(seed))
    batch = batch_from_arrays(samples["occupancy"], samples["colour"], samples["cost"],
                              samples["instruction"], vocabulary, config, 3.0)
    optimiser = torch.optim.Adam(model.parameters(), lr=1e-2)
    losses = [train_step(model, optimiser, batch) for _ in range(STEPS)]
    return losses, model, batch


@pytest.mark.parametrize("encoding", ["topdown", "voxel"])
def test_overfits_a_tiny_dataset(encoding: str, samples: dict, vocabulary: Vocabulary) -> None:
    losses, model, batch = _overfit(samples, vocabulary, encoding)
    start, end = losses[0], min(losses[-5:])
    assert end < start / FACTOR, f"loss {start:.4g} → {end:.4g} in {STEPS} steps"
    model.eval()  # type: ignore[attr-defined]
    with torch.no_grad():
        pred = model(batch.obs, batch.tokens)  # type: ignore[attr-defined,operator]
    assert pred.shape == batch.target.shape  # type: ignore[attr-defined]


def test_same_seed_same_losses(samples: dict, vocabulary: Vocabulary) -> None:
    a, _, _ = _overfit(samples, vocabulary, "topdown", seed=3)
    b, _, _ = _overfit(samples, vocabulary, "topdown", seed=3)
    assert a == b


def test_the_instruction_changes_the_prediction(samples: dict, vocabulary: Vocabulary) -> None:
    _, model, batch = _overfit(samples, vocabulary, "topdown")
    obs = batch.obs[:1]  # type: ignore[attr-defined]
    tokens = torch.from_numpy(vocabulary.batch(list(INSTRUCTIONS)))
    with torch.no_grad():
        red, blue = model(obs.expand(2, *obs.shape[1:]), tokens)  # type: ignore[operator]
    assert float((red - blue).abs().mean()) > 0.02


def test_bad_config_names_the_field() -> None:
    with pytest.raises(ConfigError, match=r"UNetConfig\.depth must be an int >= 1; got 0"):
        UNetConfig(depth=0)
