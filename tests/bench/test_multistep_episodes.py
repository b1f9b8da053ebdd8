"""Multi-step episodes with replayed programs (no LLM; perception, planning, control and checks
are real): the reference programs complete a subset of the entries on a dev seed, the
wrong-order control (the same programs, steps reversed) fails the order check, and
``run_bench`` writes the suite's records and report. A subset keeps this under a minute; the
structural test over every entry is in test_multistep.py, the full suite runs with
``voxposer bench --suite multistep --llm reference``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from voxposer.bench import BenchConfig, EpisodeJob, reset_episode, run_bench, run_episode
from voxposer.bench.multistep import get_entry
from voxposer.bench.outputs import write_outputs
from voxposer.lmp.backends.replay import ReplayBackend

#: one move, one push and a constraint clause (the slower grasp and drawer entries are left to
#: the benchmark run).
REFERENCE_SUBSET = ("hover_then_region", "push_then_away", "keep_away_then_hover")


def _job(name: str, llm: str = "reference") -> EpisodeJob:
    return EpisodeJob(name, "seen", 0, llm=llm, max_time_s=30.0, suite="multistep")


@pytest.mark.parametrize("name", REFERENCE_SUBSET)
def test_reference_programs_complete_every_step_in_order(world, name: str) -> None:
    record = run_episode(_job(name), world)
    assert record.error is None, record.error
    assert record.suite == "multistep"
    assert record.success, (record.instruction, record.reason, record.program_error)
    steps = int(record.metrics["steps"])
    times = [record.metrics[f"step{k}_t"] for k in range(1, steps + 1)]
    assert all(record.metrics[f"step{k}_ok"] == 1.0 for k in range(1, steps + 1))
    assert times == sorted(times) and times[0] > 0


@pytest.mark.parametrize("name", ["hover_then_region", "push_then_away"])
def test_the_wrong_order_control_fails_the_order_check(world, name: str) -> None:
    entry = get_entry(name)
    attrs = reset_episode(entry, world, "seen", 0).attributes
    backend = ReplayBackend(entry.wrong_order(attrs).entries(), model="wrong-order-programs")
    record = run_episode(_job(name, llm="reference-wrong-order"), world, backend)
    assert record.error is None, record.error
    assert record.attributes == attrs  # the same episode as the reference's
    assert not record.success
    assert "out of order" in record.reason and "step 2" in record.reason, record.reason
    assert record.metrics["step2_held"] == 1.0 and record.metrics["in_order"] == 0.0


def test_run_bench_writes_suite_records_and_its_report(tmp_path: Path) -> None:
    cfg = BenchConfig(suite="multistep", tasks=("hover_then_region",), splits=("seen",),
                      episodes=1, workers=1, max_time_s=30.0)
    records = run_bench(cfg, tmp_path / "episodes.jsonl")
    line = json.loads((tmp_path / "episodes.jsonl").read_text().splitlines()[0])
    assert line["suite"] == "multistep" and line["task"] == "hover_then_region"
    assert line["success"], line["reason"]
    text = write_outputs(records, tmp_path, plot=True).read_text()
    assert text.startswith("# VoxPoser multi-step instruction suite")
    assert text.strip().splitlines()[-1] == "fully_completed=1.000 episodes=1 entries=1"
    assert not (tmp_path / "success.png").exists()
