"""``voxposer learn-dynamics`` refuses bad input in one line before any work."""

from __future__ import annotations

from pathlib import Path

import pytest

from voxposer.cli import main


@pytest.mark.parametrize(("args", "message"), [
    (["--task", "oven"], "unknown --task 'oven'; tasks are: door, window, fridge"),
    (["--prior", "maybe"], "unknown --prior 'maybe'; choose one of: on, off, both"),
    (["--seeds", "0"], "--seeds"),
    (["--time-limit", "0"], "--time-limit must be > 0"),
    (["--time-limit", "-5"], "--time-limit must be > 0"),
    (["--noise-cm", "0"], "--noise-cm must be a number of centimetres > 0, got 0.0"),
    (["--noise-cm", "nan"], "--noise-cm must be a number of centimetres > 0"),
    (["--zero-shot-llm", "gpt"], "unknown --zero-shot-llm 'gpt'"),
    ([], "no zero-shot trajectory of 'door'"),
])
def test_bad_input_is_one_clear_error(args: list[str], message: str, tmp_path: Path,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["learn-dynamics", "--out", str(tmp_path / "out"), *args])
    err = capsys.readouterr().err
    assert code == 2
    assert message in " ".join(err.split())
    assert not (tmp_path / "out").exists()  # nothing was started


def test_noise_cm_sets_the_exploration_sigma(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import voxposer.cli.learn_progress as progress

    seen = {}

    def fake_learn_all(tasks, prior, seeds, config, *rest):  # type: ignore[no-untyped-def]
        seen.update(sigma=config.sigma_m, limit=config.time_limit_s)
        return 0

    monkeypatch.setattr(progress, "learn_all", fake_learn_all)
    zs = tmp_path / "out" / "zero-shot" / "door"
    zs.mkdir(parents=True)
    (zs / "reference-0.npz").write_bytes(b"")
    assert main(["learn-dynamics", "--out", str(tmp_path / "out"), "--noise-cm", "2.5",
                 "--time-limit", "60"]) == 0
    assert seen == {"sigma": pytest.approx(0.025), "limit": 60.0}
