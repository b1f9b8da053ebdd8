"""``--pool ray``: episodes run as actors on a (local) Ray cluster and are recorded like the
process pool's. Ray is an optional extra (``pip install 'voxposer[ray]'``); without it this test
is skipped and the command says how to install it."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from voxposer.bench import BenchConfig, run_bench
from voxposer.errors import VoxPoserError


def test_without_ray_the_error_says_how_to_install_it(tmp_path: Path, monkeypatch) -> None:
    if importlib.util.find_spec("ray") is not None:
        import sys

        monkeypatch.setitem(sys.modules, "ray", None)  # import ray → ImportError
    cfg = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=1, workers=1,
                      pool="ray")
    with pytest.raises(VoxPoserError, match=r"voxposer\[ray\]"):
        run_bench(cfg, tmp_path / "episodes.jsonl")


def test_episodes_run_on_a_local_ray_cluster(tmp_path: Path) -> None:
    ray = pytest.importorskip("ray", reason="the optional 'ray' extra is not installed")
    results = tmp_path / "episodes.jsonl"
    cfg = BenchConfig(tasks=("move_to_region",), splits=("seen", "unseen"), episodes=1,
                      workers=1, pool="ray")
    try:
        run_bench(cfg, results)
    finally:
        ray.shutdown()
    lines = [json.loads(x) for x in results.read_text().splitlines()]
    assert {(r["split"], r["success"]) for r in lines} == {("seen", True), ("unseen", True)}
