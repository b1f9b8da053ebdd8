"""The real model path: tiny random OWLv2 and SAM saved to disk, loaded back, run end to end.

Random weights find random things: these tests check structure (types, shapes, ranges, the
loading errors), not accuracy.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("torch")
pytest.importorskip("transformers")

from voxposer.envs import TabletopWorld
from voxposer.errors import ConfigError
from voxposer.perception import DetectedObject, Perceiver
from voxposer.perception.observation import Observation
from voxposer.perception.open_vocab import (
    OpenVocabPerceiver,
    OwlDetector,
    SamSegmenter,
    open_vocab_perceiver,
)
from voxposer.perception.recorded import RecordedObservations

QUERIES = ("block", "drawer handle")


def test_detector_boxes_are_well_formed(tiny_models: tuple[Path, Path],
                                        scene: Observation) -> None:
    detector = OwlDetector.from_pretrained(tiny_models[0], threshold=0.0, max_per_query=3)
    rgb = scene.cameras[0].rgb
    found = detector.detect(rgb, QUERIES)
    assert 0 < len(found) <= 3 * len(QUERIES)
    h, w = rgb.shape[:2]
    for d in found:
        assert d.box.shape == (4,) and d.box.dtype == np.float64
        assert 0 <= d.box[0] < d.box[2] <= w and 0 <= d.box[1] < d.box[3] <= h
        assert 0.0 <= d.score <= 1.0 and d.query in range(len(QUERIES))
    assert [d.score for d in found] == sorted((d.score for d in found), reverse=True)
    assert detector.detect(rgb, ()) == []
    strict = OwlDetector.from_pretrained(tiny_models[0], threshold=1.0)
    assert strict.detect(rgb, QUERIES) == []


def test_segmenter_gives_one_image_sized_mask_per_box(tiny_models: tuple[Path, Path],
                                                      scene: Observation) -> None:
    segmenter = SamSegmenter.from_pretrained(tiny_models[1])
    rgb = scene.cameras[1].rgb
    masks = segmenter.segment(rgb, [[10, 20, 60, 90], [100, 50, 200, 150]])
    assert masks.shape == (2, *rgb.shape[:2]) and masks.dtype == np.bool_
    assert segmenter.segment(rgb, np.zeros((0, 4))).shape == (0, *rgb.shape[:2])


def test_tiny_models_run_end_to_end(tiny_models: tuple[Path, Path], scene: Observation,
                                    world: TabletopWorld) -> None:
    source = RecordedObservations(scene, object_names=())
    perceiver = open_vocab_perceiver(source, world.grid, *tiny_models, queries=QUERIES,
                                     threshold=0.0)
    assert isinstance(perceiver, OpenVocabPerceiver) and isinstance(perceiver, Perceiver)
    names = perceiver.object_names
    assert names, "threshold 0 must keep some box"
    pattern = re.compile(r"^(block|drawer handle)( [2-9]\d*)?$")
    assert all(pattern.match(n) for n in names) and len(set(names)) == len(names)
    cloud = perceiver.point_cloud()
    assert cloud.labels.min() >= -1 and cloud.labels.max() < len(names)
    found = perceiver.detect(names[0])
    assert isinstance(found, DetectedObject) and found.name == names[0]
    assert found.position.shape == (3,) and found.aabb.shape == (2, 3)
    assert found.occupancy.shape == world.grid.shape and found.occupancy.any()
    assert found.points.shape[1] == 3 and len(found.points) == len(found.normals)
    obstacles = perceiver.scene_occupancy(names[0], holding=False)
    assert obstacles.shape == world.grid.shape and obstacles.dtype == np.bool_
    assert perceiver.sliding_axis(names[0]) is None
    source.observation = Observation(scene.time + 0.1, scene.cameras, scene.ee_position,
                                     scene.ee_quat, scene.gripper, scene.label_names)
    perceiver.point_cloud()  # a new observation: tracked (or detected again if lost)
    times = perceiver.stage_times_ms
    assert len(times["tracker"]) == 1 and len(times["detector"]) >= len(scene.cameras)
    assert all(t > 0 for stage in times.values() for t in stage)


def test_missing_weights_path_names_it_and_the_class(tmp_path: Path,
                                                     tiny_models: tuple[Path, Path]) -> None:
    missing = tmp_path / "no_such_dir"
    with pytest.raises(ConfigError, match="Owlv2ForObjectDetection") as err:
        OwlDetector.from_pretrained(missing)
    assert str(missing) in str(err.value)
    with pytest.raises(ConfigError, match="SamModel") as err:
        SamSegmenter.from_pretrained(missing)
    assert str(missing) in str(err.value)
    with pytest.raises(ConfigError, match="local Hugging Face cache"):
        OwlDetector.from_pretrained("nobody/no-such-model")  # never downloaded
    with pytest.raises(ConfigError, match=r"no config\.json"):
        SamSegmenter.from_pretrained(tmp_path)


def test_another_model_type_names_path_and_expected_class(tiny_models: tuple[Path, Path],
                                                          world: TabletopWorld,
                                                          scene: Observation) -> None:
    owl, sam = tiny_models
    source = RecordedObservations(scene, object_names=())
    with pytest.raises(ConfigError, match=r"holds a 'sam' model.*Owlv2ForObjectDetection") as err:
        open_vocab_perceiver(source, world.grid, sam, sam)
    assert str(sam) in str(err.value)
    with pytest.raises(ConfigError, match=r"holds a 'owlv2' model.*SamModel") as err:
        open_vocab_perceiver(source, world.grid, owl, owl)
    assert str(owl) in str(err.value)
