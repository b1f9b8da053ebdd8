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
