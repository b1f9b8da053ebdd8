"""The open-vocabulary perceiver behind the Perceiver protocol (with ground-truth stand-ins for
the detector and segmenter, so answers are exact)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from voxposer.envs import TabletopWorld
from voxposer.errors import ConfigError, ObjectNotVisibleError
from voxposer.perception import Perceiver
from voxposer.perception.observation import Observation
from voxposer.perception.open_vocab import DEFAULT_QUERIES, OpenVocabPerceiver
from voxposer.perception.recorded import RecordedObservations

from .ground_truth import GroundTruthModels

OBJECTS = {"block": ("blue block", "green block"), "robot": ("robot",),
           "gripper": ("gripper",)}


@pytest.fixture
def perceiver(scene: Observation, world: TabletopWorld) -> OpenVocabPerceiver:
    source = RecordedObservations(scene, object_names=())
    models = GroundTruthModels(source, OBJECTS)
    return OpenVocabPerceiver(source, world.grid, models, models,
                              queries=("block", "robot", "gripper"))


def test_it_is_a_perceiver(perceiver: OpenVocabPerceiver) -> None:
    assert isinstance(perceiver, Perceiver)
    assert set(perceiver.object_names) == {"block", "block 2", "robot", "gripper"}


def test_absent_query_names_it_and_what_was_detected(perceiver: OpenVocabPerceiver) -> None:
    with pytest.raises(ObjectNotVisibleError) as err:
        perceiver.detect("the vase")
    message = str(err.value)
    assert "'the vase'" in message
    assert all(name in message for name in ("block, ", "block 2", "robot", "gripper"))


def test_detect_matches_names_leniently(perceiver: OpenVocabPerceiver,
                                        world: TabletopWorld) -> None:
    first, second = perceiver.detect("the block"), perceiver.detect("Block 2")
    assert (first.name, second.name) == ("block", "block 2")
    truth = [world.object_position(n) for n in ("blue block", "green block")]
    for found in (first, second):
        assert min(np.linalg.norm(found.position - t) for t in truth) < 0.015
    assert not np.any(first.occupancy & second.occupancy)
    assert perceiver.sliding_axis("block") is None


def test_obstacles_leave_out_the_entity_and_the_robot(perceiver: OpenVocabPerceiver) -> None:
    block, robot = perceiver.detect("block"), perceiver.detect("robot")
    obstacles = perceiver.scene_occupancy("block", holding=False)
    assert obstacles.shape == perceiver.grid.shape
    above = int(perceiver.grid.world_to_voxel([0.0, 0.0, 0.0])[2]) + 1  # the table is unlabelled
    assert block.occupancy[:, :, above:].any() and robot.occupancy[:, :, above:].any()
    assert not np.any((obstacles & block.occupancy)[:, :, above:])
    assert not np.any((obstacles & robot.occupancy)[:, :, above:])
    assert np.all(obstacles[perceiver.detect("block 2").occupancy])


@pytest.mark.parametrize("queries", [(), ("block", ""), ("block", "the Block"), "block"])
def test_bad_queries_are_refused(queries: tuple[str, ...], scene: Observation,
                                 world: TabletopWorld) -> None:
    source = RecordedObservations(scene, object_names=())
    models = GroundTruthModels(source, OBJECTS)
    with pytest.raises(ConfigError, match="queries"):
        OpenVocabPerceiver(source, world.grid, models, models, queries=queries)


def test_default_queries_are_the_catalog_names() -> None:
    assert "top drawer handle" in DEFAULT_QUERIES and "blue block" in DEFAULT_QUERIES


def test_importing_the_package_does_not_import_torch() -> None:
    code = ("import sys, voxposer, voxposer.perception.open_vocab; "
            "print('torch' in sys.modules, 'transformers' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.split() == ["False", "False"]
