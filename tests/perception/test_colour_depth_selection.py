"""``--perception`` picks the perceiver of a simulated embodiment; bad values list the choices."""

from __future__ import annotations

import pytest

from voxposer.bench.runner import BenchConfig
from voxposer.cli.run import PERCEPTION_CHOICES
from voxposer.envs import TabletopWorld
from voxposer.errors import ConfigError
from voxposer.perception import SegmentationPerceiver
from voxposer.perception.colour_depth import ColourDepthPerceiver
from voxposer.pipeline import PERCEPTIONS, Embodiment, check_perception


def test_cli_choices_are_the_pipelines() -> None:
    # the CLI adds the learned open-vocabulary perceiver, built from model folders it is given
    assert PERCEPTION_CHOICES == (*PERCEPTIONS, "open-vocab")
    assert PERCEPTIONS == ("ground-truth", "colour-depth", "ground-truth-noisy",
                           "colour-depth-noisy", "colour-depth-tracked",
                           "colour-depth-tracked-noisy")


def test_unknown_perception_lists_the_choices() -> None:
    with pytest.raises(ConfigError, match=r"'pixels'.*ground-truth, colour-depth"):
        check_perception("pixels")
    with pytest.raises(ConfigError, match="ground-truth, colour-depth"):
        BenchConfig(tasks=("close_drawer",), episodes=1, workers=1, perception="pixels")


def test_embodiment_uses_the_chosen_perceiver(world: TabletopWorld) -> None:
    assert isinstance(Embodiment.simulated(world).perceiver, SegmentationPerceiver)
    body = Embodiment.simulated(world, "colour-depth")
    assert isinstance(body.perceiver, ColourDepthPerceiver)
