"""Instructions carried out end to end with recorded programs (the replay backend, a test double):
planner → composer → value-map LMPs → closed-loop execution in the MuJoCo world."""

import json
from pathlib import Path

import numpy as np

from voxposer.cli import main
from voxposer.control import ExecutorConfig
from voxposer.control.robot_handoff import RobotHandoff
from voxposer.envs import TabletopWorld
from voxposer.envs.layout import SceneLayout
from voxposer.lmp.backends.replay import ReplayBackend
from voxposer.lmp.runtime import LMPRuntime
from voxposer.pipeline import Embodiment, voxposer_runtime

RECORDINGS = Path(__file__).parent / "recordings" / "tabletop.jsonl"
MOVE_ABOVE_BLUE = "move to the top of the blue block while staying away from the green block"


def _run(world: TabletopWorld, instruction: str, seed: int, on_replan=None) -> RobotHandoff:
    return _run_with_runtime(world, instruction, seed, on_replan)[0]


def _run_with_runtime(
    world: TabletopWorld, instruction: str, seed: int, on_replan=None
) -> tuple[RobotHandoff, LMPRuntime]:
    runtime, executor = voxposer_runtime(
        Embodiment.simulated(world), ReplayBackend(RECORDINGS), np.random.default_rng(seed),
        executor_config=ExecutorConfig(max_time_s=30), on_replan=on_replan)
    runtime.run(instruction)
    return executor, runtime


def _run_cli(
    out: Path, instruction: str, *extra: str, recordings: Path = RECORDINGS
) -> tuple[int, dict]:
    """``voxposer run`` on the replay backend; returns the exit status and summary.json."""
    code = main(
        [
            "run",
            instruction,
            "--llm",
            "replay",
            "--recordings",
            str(recordings),
            "--out",
            str(out),
            *extra,
        ]
    )
    return code, json.loads((out / "summary.json").read_text())


def test_move_above_blue_while_avoiding_green(world: TabletopWorld) -> None:
    layout = SceneLayout(
        blocks=("blue", "green"), poses={"blue block": (0.0, -0.1), "green block": (-0.12, -0.2)}
    )
    world.reset(np.random.default_rng(0), layout)
    ex = _run(world, MOVE_ABOVE_BLUE, 0)
    (record,) = ex.records
    assert record.result.success, record.result.message
    above_blue = world.object_position("blue block") + [0, 0, 0.08 + 0.025]
    assert np.linalg.norm(world.get_ee_pose()[0] - above_blue) < 0.03
    green = world.object_position("green block")
    assert np.linalg.norm(np.asarray(record.result.trace) - green, axis=1).min() > 0.08


def test_push_block_onto_line(world: TabletopWorld) -> None:
    layout = SceneLayout(
        blocks=("blue",),
        lines=("yellow",),
        extra_blocks=(0, 0),
        extra_lines=(0, 0),
        poses={"blue block": (-0.1, -0.15), "yellow line": (0.08, 0.05, 0.0)},
    )
    world.reset(np.random.default_rng(1), layout)
    ex = _run(world, "push the blue block onto the yellow line", 1)
    assert ex.records[-1].result.success, ex.records[-1].result.message
    line = world.object_position("yellow line")
    assert np.linalg.norm(world.object_position("blue block")[:2] - line[:2]) < 0.05


def test_close_the_top_drawer(world: TabletopWorld) -> None:
    world.reset(np.random.default_rng(2), SceneLayout(drawer_openings={"top": 0.15}))
    ex = _run(world, "close the top drawer", 2)
    assert ex.records[-1].result.success, ex.records[-1].result.message
    assert world.drawer_opening("top") < 0.02


def test_displaced_target_still_succeeds_without_new_llm_calls(world: TabletopWorld) -> None:
    layout = SceneLayout(
        blocks=("blue", "green"), poses={"blue block": (0.05, 0.1), "green block": (-0.3, -0.3)}
    )
    world.reset(np.random.default_rng(3), layout)
    displaced = []

    def disturb(result, plan) -> None:
        if result.replans == 3 and not displaced:
            displaced.append(world.displace_object(np.random.default_rng(9), "blue block"))

    executor, runtime = _run_with_runtime(world, MOVE_ABOVE_BLUE, 3, disturb)
    calls = runtime.llm_calls
    assert displaced
    assert executor.records[-1].result.success
    above_blue = world.object_position("blue block") + [0, 0, 0.105]
    assert np.linalg.norm(world.get_ee_pose()[0] - above_blue) < 0.03
    # planner, composer, 2 map LMPs (the 3 parse_query_obj queries name scene objects exactly
    # and need no model): no call per replan
    assert calls == 4


def test_voxposer_run_writes_video_pictures_transcript_and_summary(tmp_path: Path) -> None:
    out = tmp_path / "run"
    code, summary = _run_cli(out, MOVE_ABOVE_BLUE, "--seed", "5")
    assert code == 0 and summary["success"], summary
    assert (out / "rollout.mp4").stat().st_size > 10_000
    assert (out / "subtask_01.html").stat().st_size > 100_000
    events = [json.loads(line) for line in (out / "transcript.jsonl").read_text().splitlines()]
    assert {e["event"] for e in events} >= {"llm_call", "exec"}
    assert summary["llm_calls"] == 4 and summary["subtasks"][0]["replans"] > 1  # names resolved
    assert 100 < summary["peak_rss_mb"] < 64 * 1024  # this process's peak memory, in MiB


def test_voxposer_run_fails_cleanly_for_an_unknown_object(tmp_path: Path) -> None:
    out = tmp_path / "run"
    code, summary = _run_cli(out, "move to the top of the silver sphere", "--no-video")
    assert code == 1 and not summary["success"]
    assert "silver sphere" in summary["message"] and "the scene has" in summary["message"]


def test_voxposer_run_reports_a_missing_recordings_file(tmp_path: Path) -> None:
    out = tmp_path / "run"
    code, summary = _run_cli(
        out, "close the top drawer", "--no-video", recordings=tmp_path / "none.jsonl"
    )
    assert code == 1 and not summary["success"]
    assert "does not exist" in summary["message"]


def test_voxposer_run_recovers_from_disturbances(tmp_path: Path) -> None:
    out = tmp_path / "run"
    code, summary = _run_cli(out, "close the top drawer", "--no-video", "--disturb", "--seed", "3")
    kinds = {d["kind"] for d in summary["disturbances"]}
    assert "revert_progress" in kinds, summary["disturbances"]  # the drawer was pulled open again
    assert code == 0 and summary["success"], summary["message"]
