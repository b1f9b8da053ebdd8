"""``voxposer bench-data`` and ``voxposer train-unet``: bad input is one line before any work;
one episode of data trains one epoch end to end."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from voxposer.cli import main


@pytest.mark.parametrize(("args", "message"), [
    (["--episodes", "0"], "--episodes must be an integer >= 1"),
    (["--seeds", "100000-100002"], "seed 100000 is not a dev seed"),
    (["--seeds", "a-b"], "--seeds must be 'dev' or a list"),
    (["--tasks", "juggle"], "unknown --tasks juggle; tasks are: "),
])
def test_bench_data_refuses_bad_input(args: list[str], message: str, tmp_path: Path,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["bench-data", "--out", str(tmp_path / "d"), *args])
    assert code == 2
    assert message in " ".join(capsys.readouterr().err.split())
    assert not (tmp_path / "d").exists()


@pytest.mark.parametrize(("args", "message"), [
    (["--epochs", "0"], "--epochs must be an integer >= 1"),
    (["--loss", "l3"], "unknown --loss 'l3'; choose one of: mse, smooth_l1"),
    (["--encoding", "rgbd"], "unknown --encoding 'rgbd'; choose one of: topdown, voxel"),
    ([], "holds no manifest.json"),
])
def test_train_unet_refuses_bad_input(args: list[str], message: str, tmp_path: Path,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["train-unet", "--data", str(tmp_path / "none"), "--out", str(tmp_path / "o"),
                 *args])
    assert code == 2
    assert message in " ".join(capsys.readouterr().err.split())
    assert not (tmp_path / "o").exists()


def test_one_episode_of_data_trains_one_epoch(tmp_path: Path) -> None:
    pytest.importorskip("torch")
    data, out = tmp_path / "data", tmp_path / "unet"
    assert main(["bench-data", "--out", str(data), "--episodes", "1",
                 "--tasks", "move_to_region"]) == 0
    manifest = json.loads((data / "manifest.json").read_text())
    assert manifest["done"] == {"move_to_region": [0]}
    assert main(["bench-data", "--out", str(data), "--episodes", "1",
                 "--tasks", "move_to_region"]) == 2  # exists: needs --resume
    assert main(["train-unet", "--data", str(data), "--out", str(out), "--epochs", "1",
                 "--base-channels", "4"]) == 0
    assert (out / "model.pt").exists() and (out / "checkpoints" / "epoch_001.pt").exists()
    assert (out / "loss.png").stat().st_size > 1000
    assert len(json.loads((out / "losses.json").read_text())["epoch"]) == 1
