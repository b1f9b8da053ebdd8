"""Tracking: masks carried between frames keep each object's identity without re-detecting."""

from __future__ import annotations

import numpy as np
import pytest

from voxposer.envs import TabletopWorld
from voxposer.errors import ConfigError
from voxposer.perception.observation import Observation
from voxposer.perception.open_vocab.perceiver import OpenVocabPerceiver
from voxposer.perception.open_vocab.tracker import MaskTracker
from voxposer.perception.recorded import RecordedObservations

from .conftest import BLUE, two_blocks
from .ground_truth import GroundTruthModels

BLOCKS = {"block": ("blue block", "green block")}


def _perceiver(obs: Observation, world: TabletopWorld
               ) -> tuple[OpenVocabPerceiver, RecordedObservations, GroundTruthModels]:
    source = RecordedObservations(obs, object_names=())
    models = GroundTruthModels(source, BLOCKS)
    return (OpenVocabPerceiver(source, world.grid, models, models, queries=("block",)),
            source, models)


def _name_of(perceiver: OpenVocabPerceiver, position: np.ndarray) -> str:
    """The name of the detected object nearest ``position`` [m] (x, y)."""
    return min(perceiver.object_names,
               key=lambda n: float(np.linalg.norm(perceiver.detect(n).position[:2]
                                                  - position[:2])))


def test_identity_kept_across_a_5_cm_displacement(world: TabletopWorld) -> None:
    perceiver, source, _ = _perceiver(two_blocks(world), world)
    blue_name = _name_of(perceiver, np.array(BLUE))
    assert sorted(perceiver.object_names) == ["block", "block 2"]
    assert perceiver.detector_runs == 1
    before = {inst.name: inst.centroid for inst in perceiver.instances}
    source.observation = two_blocks(world, blue=(BLUE[0] + 0.05, BLUE[1], 0.0))
    found = perceiver.detect(blue_name)
    assert perceiver.detector_runs == 1 and len(perceiver.stage_times_ms["tracker"]) == 1
    assert np.linalg.norm(found.position - world.object_position("blue block")) < 0.015
    assert np.linalg.norm(found.position[:2] - before[blue_name][:2]) > 0.04  # it moved
    other = next(n for n in perceiver.object_names if n != blue_name)
    assert np.linalg.norm(perceiver.detect(other).position
                          - world.object_position("green block")) < 0.015


def test_a_jump_beyond_max_step_runs_the_detector_again(world: TabletopWorld) -> None:
    perceiver, source, models = _perceiver(two_blocks(world), world)
    assert len(perceiver.object_names) == 2 and perceiver.detector_runs == 1
    source.observation = two_blocks(world, blue=(BLUE[0] + 0.2, BLUE[1] - 0.1, 0.0))
    assert sorted(perceiver.object_names) == ["block", "block 2"]
    assert perceiver.detector_runs == 2
    assert models.detect_calls == 2 * len(source.observation.cameras)
    names = {_name_of(perceiver, world.object_position(c)) for c in ("blue block", "green block")}
    assert names == {"block", "block 2"}


def test_new_queries_run_the_detector_again(world: TabletopWorld) -> None:
    perceiver, _, _ = _perceiver(two_blocks(world), world)
    assert perceiver.object_names
    perceiver.set_queries(["vase"])
    assert perceiver.object_names == () and perceiver.detector_runs == 2


@pytest.mark.parametrize("field, value", [("margin", 0.0), ("min_iou", 1.5),
                                          ("min_pixels", 0), ("max_step_m", -1.0)])
def test_tracker_rejects_bad_settings(field: str, value: float) -> None:
    with pytest.raises(ConfigError, match=field):
        MaskTracker(segmenter=None, **{field: value})  # type: ignore[arg-type]
