"""``voxposer bench`` flags: seed sets, instruction splits, the constraint-blind control's skipped
tasks, --fresh-cache and --allow-mixed-versions reaching the runner (run_bench is stubbed)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, ClassVar

import pytest

from voxposer.bench.tasks import TASKS
from voxposer.bench.tasks.move_to_region import MoveToRegion
from voxposer.cli import bench as bench_cmd
from voxposer.errors import ConfigError


class _Constrained(MoveToRegion):
    name = "constrained"
    constraint: ClassVar[str | None] = "avoidance map"

    def blind(self, attrs):
        return self.reference(attrs)


def _args(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    bench_cmd.add_parser(parser.add_subparsers())
    return parser.parse_args(["bench", *argv])


def test_seed_and_instruction_flags() -> None:
    cfg = bench_cmd._config(_args("--seeds", "test", "--episodes", "20", "--llm", "default",
                                  "--instructions", "unseen"))
    assert list(cfg.seed_list()) == list(range(100_000, 100_020))
    assert cfg.instructions == "unseen"
    assert bench_cmd._default_out(cfg) == "voxposer-default-test-unseen-instructions"
    assert bench_cmd._default_out(bench_cmd._config(_args("--llm", "default"))) == \
        "voxposer-default"
    assert bench_cmd._config(_args("--seed", "5", "--episodes", "2")).seed_set == "adhoc"
    with pytest.raises(ConfigError, match=r"dev .*test "):
        bench_cmd._config(_args("--seeds", "final"))
    with pytest.raises(ConfigError, match="seen, unseen"):
        bench_cmd._config(_args("--instructions", "maybe"))
    with pytest.raises(ConfigError, match="reference"):
        bench_cmd._config(_args("--llm", "reference", "--instructions", "unseen"))


def test_blind_run_says_which_tasks_it_skips(tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.setitem(TASKS, "constrained", _Constrained())
    seen: dict[str, Any] = {}

    def fake_run_bench(cfg, results, **kwargs):
        seen.update(cfg=cfg, results=results, **kwargs)
        return []

    monkeypatch.setattr(bench_cmd, "run_bench", fake_run_bench)
    args = _args("--tasks", "move_to_region,constrained", "--llm", "reference-blind",
                 "--episodes", "1", "--out", str(tmp_path), "--fresh-cache",
                 "--allow-mixed-versions", "--no-plot")
    assert bench_cmd.run(args) == 0
    err = capsys.readouterr().err
    assert "skipped (no constraint, so no blind control): move_to_region" in err
    assert [j.task for j in seen["cfg"].jobs()] == ["constrained", "constrained"]
    assert seen["cfg"].fresh_cache and seen["allow_mixed_versions"]
    assert seen["results"] == tmp_path / "episodes.jsonl"
