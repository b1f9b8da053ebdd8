"""Fixtures of the open-vocabulary tests: a two-block scene and tiny random models on disk."""

from __future__ import annotations

import os
from pathlib import Path

os.environ["HF_HUB_OFFLINE"] = "1"
os.environ["TRANSFORMERS_OFFLINE"] = "1"

import numpy as np
import pytest

from voxposer.envs import SceneLayout, TabletopWorld
from voxposer.perception.observation import Observation

#: Where the two blocks stand [m] (x, y, yaw), axis-aligned.
BLUE = (-0.20, -0.10, 0.0)
GREEN = (-0.05, 0.12, 0.0)


def two_blocks(world: TabletopWorld, blue: tuple[float, float, float] = BLUE) -> Observation:
    """The world reset with a blue and a green block (no cabinet, no distractors) and its
    observation."""
    world.reset(np.random.default_rng(0),
                SceneLayout(blocks=("blue", "green"), extra_blocks=(0, 0), extra_lines=(0, 0),
                            cabinet=False, poses={"blue block": blue, "green block": GREEN}))
    return world.observe(rgb=True)


@pytest.fixture(scope="module")
def scene(world: TabletopWorld) -> Observation:
    return two_blocks(world)


@pytest.fixture(scope="session")
def tiny_models(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """Tiny random OWLv2 (with its tokenizer) and SAM saved to a temporary directory."""
    pytest.importorskip("transformers")
    from voxposer.perception.open_vocab.tiny_models import save_tiny_models

    return save_tiny_models(tmp_path_factory.mktemp("tiny_models"))
