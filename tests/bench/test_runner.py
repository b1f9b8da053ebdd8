"""The runner: records appended as JSONL (stamped with the code version, seed set and instruction
split), --resume skips finished episodes, a crashed episode is recorded with its traceback and
the run goes on, reports and the chart are written."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from voxposer.bench import BenchConfig, run_bench
from voxposer.bench.outputs import write_outputs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks import TASKS, get_task
from voxposer.bench.version import code_version
from voxposer.errors import ConfigError


class _Crashing(BenchTask):
    name = "crashing"
    category = "Spatial Composition"
    template = "move to the [region]"
    paper_row = "move to the [region]"

    def layout(self, rng, attrs):
        return get_task("move_to_region").layout(rng, attrs)

    def check(self, world, trace, attrs, tol) -> Verdict:
        if len(trace) > 1:
            raise RuntimeError("checker bug")
        return Verdict(False, "not yet", {})

    def reference(self, attrs):
        return get_task("move_to_region").reference(attrs)


def test_config_lists_known_names() -> None:
    with pytest.raises(ConfigError, match="llm_primitives"):
        BenchConfig(method="nope")
    with pytest.raises(ConfigError, match="move_to_region"):
        BenchConfig(tasks=("nope",))
    with pytest.raises(ConfigError, match="reference, reference-blind, default"):
        BenchConfig(llm="gpt-17")


def test_jsonl_resume_crash_and_report(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setitem(TASKS, "crashing", _Crashing())
    results = tmp_path / "episodes.jsonl"
    cfg = BenchConfig(tasks=("move_to_region", "crashing"), splits=("seen",), episodes=1,
                      workers=1, max_time_s=20.0)
    seen = []
    records = run_bench(cfg, results, on_record=seen.append)
    lines = [json.loads(x) for x in results.read_text().splitlines()]
    assert len(lines) == len(seen) == len(records) == 2
    crashed = next(r for r in lines if r["task"] == "crashing")
    assert "checker bug" in crashed["error"] and "Traceback" in crashed["error"]
    assert next(r for r in lines if r["task"] == "move_to_region")["success"]
    assert {(r["code_hash"], r["seed_set"], r["instructions"]) for r in lines} == {
        (code_version().code_hash, "dev", "seen")}
    with pytest.raises(ConfigError, match="--resume"):
        run_bench(cfg, results)
    more = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=2, workers=1)
    new = []
    run_bench(more, results, resume=True, on_record=new.append)
    assert [r["seed"] for r in new] == [1]  # seed 0 was already there
    monkeypatch.delitem(TASKS, "crashing")
    kept = [r for r in lines if r["task"] != "crashing"]
    report = write_outputs(kept, tmp_path, plot=True)
    text = report.read_text()
    assert "reference programs" in text and "corner_radius_m" in text
    for task in TASKS.values():  # every task has its row, with this run's numbers where run
        row = [ln for ln in text.splitlines() if ln.startswith(f"| {task.template} | ")]
        assert row, task.name
        assert row[0].startswith(f"| {task.template} | "
                                 + ("100.0% (1/1) | — |" if task.name == "move_to_region"
                                    else "— | — |"))
    replays = sum(r["llm_calls"] for r in kept)
    assert replays > 0
    assert f"reference-program replays** (no LLM): {replays} over {len(kept)} episodes" in text
    assert f"`{code_version().code_hash}`" in text and "seeds 0–0 (1 distinct)" in text
    assert (tmp_path / "success.png").stat().st_size > 10_000
