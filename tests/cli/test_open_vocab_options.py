"""``--perception open-vocab --detector DIR --segmenter DIR``: refused without both model
folders or with folders that hold no model, and on recorded frames it builds the learned
perceiver from the folders (tiny random-weight OWLv2 and SAM, test doubles built here)."""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest

pytest.importorskip("torch")
pytest.importorskip("transformers")

import voxposer.cli as cli
from voxposer.cli import run
from voxposer.cli.run_frames import frames_embodiment
from voxposer.errors import ConfigError
from voxposer.perception.open_vocab import OpenVocabPerceiver
from voxposer.perception.open_vocab.tiny_models import save_tiny_models


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str], tmp_path: Path,
             monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.setattr(run, "_rollout", lambda *a, **k: pytest.fail("work started"))
    assert cli.main([*argv, "--out", str(tmp_path / "out")]) == 2
    captured = capsys.readouterr()
    lines = [ln for ln in (captured.err + captured.out).splitlines() if ln.strip()]
    assert len(lines) == 1, lines
    return lines[0]


def test_open_vocab_needs_both_model_folders(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    line = _refused(["run", "push the blue block", "--perception", "open-vocab"], capsys,
                    tmp_path, monkeypatch)
    assert "--detector" in line
    line = _refused(["run", "push the blue block", "--perception", "open-vocab", "--detector",
                     str(tmp_path)], capsys, tmp_path, monkeypatch)
    assert "--segmenter" in line


def test_model_folders_without_open_vocab_are_refused(capsys: pytest.CaptureFixture[str],
                                                      tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    line = _refused(["run", "push the blue block", "--detector", str(tmp_path)], capsys,
                    tmp_path, monkeypatch)
    assert "open-vocab" in line and "ground-truth" in line


def test_a_missing_model_folder_is_named(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                                         monkeypatch: pytest.MonkeyPatch) -> None:
    missing = tmp_path / "no" / "such" / "owlv2"
    line = _refused(["run", "push the blue block", "--perception", "open-vocab", "--detector",
                     str(missing), "--segmenter", str(tmp_path)], capsys, tmp_path, monkeypatch)
    assert str(missing) in line and "--detector" in line


def test_frames_with_open_vocab_build_the_learned_perceiver(tmp_path: Path) -> None:
    frames = tmp_path / "frames"
    assert cli.main(["render", "--seed", "2", "--width", "160", "--height", "120",
                     "--save-frames", str(frames)]) == 0
    detector, segmenter = save_tiny_models(tmp_path / "models")
    args = argparse.Namespace(detector=str(detector), segmenter=str(segmenter),
                              detector_threshold=0.0)
    _, body = frames_embodiment(frames, "open-vocab", args)
    assert isinstance(body.perceiver, OpenVocabPerceiver)
    cloud = body.perceiver.point_cloud()
    assert len(cloud) > 0 and cloud.points.shape == (len(cloud), 3)


def test_a_folder_of_another_model_type_is_refused(tmp_path: Path) -> None:
    detector, segmenter = save_tiny_models(tmp_path / "models")
    frames = tmp_path / "frames"
    assert cli.main(["render", "--seed", "2", "--width", "160", "--height", "120",
                     "--save-frames", str(frames)]) == 0
    swapped = argparse.Namespace(detector=str(segmenter), segmenter=str(detector),
                                 detector_threshold=0.1)
    with pytest.raises(ConfigError, match="Owlv2ForObjectDetection"):
        frames_embodiment(frames, "open-vocab", swapped)
