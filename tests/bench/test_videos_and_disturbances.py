"""``--video`` and ``--disturb`` on real episodes: a failed episode leaves an MP4 with frames, a
successful one none; disturbed episodes record what was applied (the drawer pulled open again,
the named block displaced, the baseline on sim time); static and disturbed records of one
episode are distinct identities in one file, and the report puts them side by side."""

from __future__ import annotations

import json
from pathlib import Path

import imageio.v2 as imageio
import numpy as np
import pytest

from voxposer.bench import BenchConfig, EpisodeJob, run_bench, run_episode
from voxposer.bench.config import Tolerances
from voxposer.bench.report import markdown
from voxposer.bench.task import reset_episode
from voxposer.bench.tasks import get_task
from voxposer.errors import ConfigError
from voxposer.lmp.backends.replay import ReplayBackend


def _frames(path: Path) -> int:
    reader = imageio.get_reader(path)
    try:
        return sum(1 for _ in reader)
    finally:
        reader.close()


def test_unknown_video_modes_list_the_allowed_ones() -> None:
    with pytest.raises(ConfigError, match="none, failures, all"):
        BenchConfig(tasks=("move_to_region",), video="failed")


def test_a_failed_episode_keeps_its_video(tmp_path: Path) -> None:
    # the constraint-blind control of "move … at a faster speed in [region]" moves at 1x: fails
    cfg = BenchConfig(tasks=("move_to_pos_velocity_in_region",), splits=("seen",), episodes=1,
                      llm="reference-blind", workers=1, video="failures")
    (rec,) = run_bench(cfg, tmp_path / "episodes.jsonl")
    assert not rec["success"]
    assert rec["video"] == ("videos/voxposer-reference-blind-seen-move_to_pos_velocity_in_region"
                            "-seen-0.mp4")
    assert _frames(tmp_path / rec["video"]) > 5
    report = markdown([rec], Tolerances(), out=tmp_path)
    assert f"]({rec['video']})" in report and "## Failure modes" in report


def test_static_and_disturbed_episodes_share_a_file(tmp_path: Path) -> None:
    results = tmp_path / "episodes.jsonl"
    static = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=1, workers=1,
                         video="failures")
    (first,) = run_bench(static, results)
    assert first["success"] and first["video"] is None and not first["disturbed"]
    assert not (tmp_path / "videos").exists() or not any((tmp_path / "videos").iterdir())
    starts: list[tuple[int, int]] = []
    shaken = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=1, workers=1,
                         disturb=True)
    records = run_bench(shaken, results, resume=True, on_start=lambda *a: starts.append(a))
    assert starts == [(1, 0)]  # the static record does not count as the disturbed one
    assert [r["disturbed"] for r in records] == [False, True]
    assert records[1]["disturbances"], "a disturbed episode records what was applied"
    assert len(results.read_text().splitlines()) == 2
    run_bench(shaken, results, resume=True, on_start=lambda *a: starts.append(a))
    assert starts[-1] == (0, 1)  # and the disturbed one is found again
    report = markdown(records, Tolerances())
    (row,) = [ln for ln in report.split("## Static vs disturbed")[1].splitlines()
              if ln.startswith("| move to the [region] | seen |")]
    assert row.count("(1/1)") + row.count("(0/1)") == 2  # a static and a disturbed cell


def test_a_disturbed_drawer_is_pulled_open_again(world) -> None:
    rec = run_episode(EpisodeJob("close_drawer", "seen", 0, disturbed=True), world)
    assert rec.disturbed and rec.error is None
    (revert,) = [d for d in rec.disturbances if d["kind"] == "revert_progress"]
    assert revert["target"].endswith("drawer") and revert["entity"].endswith("drawer handle")
    assert 0.4 <= revert["progress"] < 1.0  # on the schedule, while the drawer was closing
    assert np.linalg.norm(revert["after"]) > 10.0  # a pull [N] along the opening direction


def test_a_gripper_episode_displaces_the_named_block(world) -> None:
    rec = run_episode(EpisodeJob("move_to_preposition", "seen", 0, disturbed=True), world)
    (moved,) = [d for d in rec.disturbances if d["kind"] == "displace_object"]
    assert moved["target"] == rec.attributes["obj"] and moved["entity"] == "gripper"
    assert np.linalg.norm(np.subtract(moved["after"], moved["before"])) >= 0.08
    assert rec.disturbances[0]["kind"] == "push_robot"
    assert json.loads(json.dumps(rec.to_json()))["disturbances"] == rec.disturbances


def test_the_baseline_is_disturbed_on_sim_time(world) -> None:
    job = EpisodeJob("move_to_region", "seen", 0, method="llm_primitives", llm="replay",
                     disturbed=True)
    code = "\n".join(["move_to_pos([-0.2, 0.2, 0.3])", "move_to_pos([-0.2, -0.2, 0.3])",
                      "move_to_pos([-0.1, 0.25, 0.2])", "move_to_pos([-0.2, 0.0, 0.3])"])
    instruction = reset_episode(get_task(job.task), world, job.split, job.seed).instruction
    backend = ReplayBackend([{"lmp": "llm_primitives", "query": instruction,
                              "responses": [code]}])
    rec = run_episode(job, world, backend)
    assert rec.error is None, rec.error
    kinds = [d["kind"] for d in rec.disturbances]
    assert kinds[:1] == ["push_robot"] and "revert_progress" not in kinds  # the hand: no revert
    assert all(d["progress"] is None for d in rec.disturbances)
    assert rec.disturbances[0]["sim_time_s"] >= 1.0
