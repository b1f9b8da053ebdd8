"""The runner: records appended as JSONL, --resume skips finished episodes, a crashed episode is
recorded with its traceback and the run goes on, reports and the chart are written."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from voxposer.bench import BenchConfig, run_bench
from voxposer.bench.bench_cmd import write_outputs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks import TASKS, get_task
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
    with pytest.raises(ConfigError, match="reference"):
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
    with pytest.raises(ConfigError, match="--resume"):
        run_bench(cfg, results)
    more = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=2, workers=1)
    new = []
    run_bench(more, results, resume=True, on_record=new.append)
    assert [r["seed"] for r in new] == [1]  # seed 0 was already there
    monkeypatch.delitem(TASKS, "crashing")
    report = write_outputs([r for r in lines if r["task"] != "crashing"], tmp_path, plot=True)
    text = report.read_text()
    assert "reference programs" in text and "corner_radius_m" in text
    assert "| move to the [region] | 100.0% (1/1) |" in text
    assert (tmp_path / "success.png").stat().st_size > 10_000
    assert np.isfinite(len(text))
