"""Long benchmark runs survive being stopped: ``voxposer bench`` (a subprocess, reference
programs, one task, ``--workers 1``) stopped by SIGTERM, or by SIGINT while started as a
background job that ignores SIGINT, keeps whole lines, exits non-zero saying how to resume, and
the printed ``--resume`` command finishes the run; killed with SIGKILL (and a torn last line),
``--resume`` reruns only the episodes that were not written."""

from __future__ import annotations

import json
import os
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from voxposer.cli import main

BENCH = ["bench", "--llm", "reference", "--tasks", "move_to_region", "--splits", "seen",
         "--workers", "1", "--no-plot"]
#: How long a stopped run may take to start and write its first episode [s] (a loaded CPU).
FIRST_EPISODE_S = 300.0


def _start(out: Path, episodes: int, *, ignore_sigint: bool = False) -> subprocess.Popen[str]:
    """``python -m voxposer.cli bench …`` writing to ``out``; with ``ignore_sigint`` it starts
    with SIGINT ignored, as a non-interactive shell starts a background job (``cmd &``)."""
    def background() -> None:
        signal.signal(signal.SIGINT, signal.SIG_IGN)

    return subprocess.Popen(
        [sys.executable, "-m", "voxposer.cli", *BENCH, "--episodes", str(episodes),
         "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env={**os.environ, "MUJOCO_GL": "egl"}, preexec_fn=background if ignore_sigint else None)


def _records(path: Path) -> list[dict]:
    """Every line of ``path`` as JSON (a torn line fails the test)."""
    return [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []


def _wait_for_episode(proc: subprocess.Popen[str], results: Path) -> None:
    """Until ``results`` holds a whole line (the run is inside its episode loop)."""
    deadline = time.monotonic() + FIRST_EPISODE_S
    while time.monotonic() < deadline:
        if results.exists() and results.read_bytes().count(b"\n") >= 1:
            return
        if proc.poll() is not None:
            pytest.fail(f"the run ended early ({proc.returncode}): {proc.communicate()[1]}")
        time.sleep(0.25)
    proc.kill()
    pytest.fail(f"no episode within {FIRST_EPISODE_S} s")


def _stop(proc: subprocess.Popen[str], signum: int) -> tuple[int, str]:
    proc.send_signal(signum)
    try:
        _, err = proc.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail(f"the run did not stop within 120 s of {signal.Signals(signum).name}")
    return proc.returncode, " ".join(err.split())


def _seeds(records: list[dict]) -> list[int]:
    return sorted(r["seed"] for r in records)


def test_sigterm_stops_the_run_and_the_printed_resume_finishes_it(tmp_path: Path) -> None:
    out = tmp_path / "bench"
    results = out / "episodes.jsonl"
    proc = _start(out, 3)
    _wait_for_episode(proc, results)
    code, err = _stop(proc, signal.SIGTERM)
    assert code == 128 + signal.SIGTERM, err
    assert "stopped by SIGTERM" in err and "Traceback" not in err
    kept = _records(results)
    assert 1 <= len(kept) <= 3 and all(r["error"] is None for r in kept)
    assert (out / "report.md").exists()  # the report of what was kept
    command = err.rsplit("continue with: ", 1)[1]
    argv = shlex.split(command)
    assert argv[0] == "voxposer" and argv[-1] == "--resume" and str(out) in argv
    assert main(argv[1:]) == 0
    records = _records(results)
    assert _seeds(records) == [0, 1, 2]
    assert records[:len(kept)] == kept and all(r["error"] is None for r in records)


def test_sigint_stops_a_background_run_that_ignores_it(tmp_path: Path) -> None:
    out = tmp_path / "bench"
    results = out / "episodes.jsonl"
    proc = _start(out, 3, ignore_sigint=True)
    _wait_for_episode(proc, results)
    code, err = _stop(proc, signal.SIGINT)
    assert code == 128 + signal.SIGINT, err
    assert "stopped by SIGINT" in err and "--resume" in err and "Traceback" not in err
    kept = _records(results)
    assert 1 <= len(kept) <= 3 and len({r["seed"] for r in kept}) == len(kept)


def test_after_kill_9_resume_reruns_only_what_was_lost(tmp_path: Path) -> None:
    out = tmp_path / "bench"
    results = out / "episodes.jsonl"
    proc = _start(out, 3)
    _wait_for_episode(proc, results)
    proc.kill()
    proc.communicate(timeout=60)
    kept = _records(results)
    with results.open("a") as fh:  # a record cut short by the kill
        fh.write('{"task": "move_to_region", "split": "seen", "seed": 9')
    assert main([*BENCH, "--episodes", "3", "--out", str(out), "--resume"]) == 0
    records = _records(results)  # no torn line left behind
    assert _seeds(records) == [0, 1, 2] and records[:len(kept)] == kept


def test_a_whole_last_record_keeps_its_line_and_a_torn_one_is_cut(tmp_path: Path) -> None:
    from voxposer.bench.results import repair_torn_tail

    path = tmp_path / "episodes.jsonl"
    path.write_text('{"seed": 0}\n{"seed": 1}')  # killed before the newline
    assert repair_torn_tail(path) == 0 and path.read_text() == '{"seed": 0}\n{"seed": 1}\n'
    path.write_text('{"seed": 0}\n{"seed": 1, "ta')  # killed mid-record
    assert repair_torn_tail(path) == len('{"seed": 1, "ta')
    assert path.read_text() == '{"seed": 0}\n'
    assert repair_torn_tail(path) == 0 and repair_torn_tail(tmp_path / "none.jsonl") == 0
