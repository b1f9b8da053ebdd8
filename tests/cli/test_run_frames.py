"""``voxposer render --save-frames`` and ``voxposer run --frames DIR --robot none``: recorded
frames are written readably, and planning on them gives the plan the live world gives (recorded
programs, the replay backend, stand in for the language model)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from voxposer.cli import main
from voxposer.cli.render import scene_world
from voxposer.control import ExecutorConfig
from voxposer.control.plan_only import NoRobotError, RecordedPoseRobot
from voxposer.lmp.backends.replay import ReplayBackend
from voxposer.perception.frames import RecordedFrames, load_frames
from voxposer.pipeline import Embodiment, voxposer_runtime

RECORDINGS = Path(__file__).parents[1] / "control" / "recordings" / "tabletop.jsonl"
MOVE_ABOVE_BLUE = "move to the top of the blue block while staying away from the green block"
SEED, WIDTH, HEIGHT = 2, 320, 240  # seed 2: the blue and the green block are on the table
VOXEL_M = 0.01  # the tabletop grid: 1 m over 100 voxels per axis


def _render(folder: Path, *extra: str) -> int:
    return main(["render", "--seed", str(SEED), "--width", str(WIDTH), "--height", str(HEIGHT),
                 "--save-frames", str(folder), *extra])


@pytest.fixture(scope="module")
def frames(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The seeded scene's frames, saved with their labels."""
    folder = tmp_path_factory.mktemp("frames")
    assert _render(folder, "--with-labels") == 0
    return folder


def _run_frames(frames: Path, out: Path, *extra: str, recordings: Path = RECORDINGS,
                instruction: str = MOVE_ABOVE_BLUE) -> tuple[int, dict]:
    code = main(["run", instruction, "--frames", str(frames), "--robot", "none", "--llm",
                 "replay", "--recordings", str(recordings), "--out", str(out), *extra])
    return code, json.loads((out / "summary.json").read_text())


def _live_first_plan(perception: str) -> np.ndarray:
    """The first planned path [m], shape (N, 3), of the live run in the seeded world."""
    world = scene_world(SEED, WIDTH, HEIGHT)
    try:
        runtime, handoff = voxposer_runtime(
            Embodiment.simulated(world, perception), ReplayBackend(RECORDINGS),
            np.random.default_rng(0), executor_config=ExecutorConfig(max_time_s=0.1))
        handoff.keep_going = True  # the first plan is all this compares
        runtime.run(MOVE_ABOVE_BLUE)
        plan = handoff.records[0].result.first_plan
        assert plan is not None
        return plan.trajectory.positions
    finally:
        world.close()


def test_render_save_frames_writes_a_readable_folder(tmp_path: Path,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    assert _render(tmp_path / "f") == 0
    assert not (tmp_path / "views.png").exists()  # only the frames were asked for
    obs = load_frames(tmp_path / "f")
    assert [c.name for c in obs.cameras] == ["front_left", "front_right", "back_left",
                                             "back_right"]
    for cam in obs.cameras:
        assert cam.rgb.shape == (HEIGHT, WIDTH, 3) and cam.rgb.std() > 10  # a picture
        assert 0.3 < float(np.median(cam.depth[np.isfinite(cam.depth)])) < 2.0  # the table [m]
        assert (cam.object_ids == -1).all()  # no labels by default: a real camera has none
    world = scene_world(SEED, WIDTH, HEIGHT)
    try:
        np.testing.assert_allclose(obs.ee_position, world.get_ee_pose()[0], atol=1e-9)
        truth = world.observe().cameras[0]
    finally:
        world.close()
    np.testing.assert_array_equal(obs.cameras[0].rgb, truth.rgb)
    np.testing.assert_allclose(obs.cameras[0].intrinsics, truth.intrinsics)


def test_with_labels_writes_the_ground_truth_channel(frames: Path) -> None:
    source = RecordedFrames(frames)
    assert source.has_labels
    assert {"blue block", "green block"} <= set(source.object_names)
    assert source.gripper_opening_m is not None and source.gripper_opening_m > 0.05


@pytest.mark.parametrize("perception", ["colour-depth", "ground-truth"])
def test_frames_give_the_live_worlds_plan(frames: Path, tmp_path: Path, perception: str
                                          ) -> None:
    code, summary = _run_frames(frames, tmp_path / "run", "--perception", perception)
    assert code == 0 and summary["success"], summary["message"]
    assert summary["reason"] == "planned" and summary["robot"] == "none"
    assert summary["perception"] == perception
    assert (tmp_path / "run" / "subtask_01.html").stat().st_size > 100_000
    plan = json.loads((tmp_path / "run" / "plan.json").read_text())
    recorded = np.asarray(plan["waypoints_m"])
    np.testing.assert_allclose(recorded[0], load_frames(frames).ee_position, atol=VOXEL_M)
    live = _live_first_plan(perception)
    # 1 mm depth steps may move a surface across a voxel boundary (here the block's top: the
    # target can lie one voxel higher), so the paths agree to within one voxel, both ways
    gaps = np.linalg.norm(recorded[:, None] - live[None], axis=2)
    assert gaps.min(axis=1).max() <= VOXEL_M + 1e-9 and gaps.min(axis=0).max() <= VOXEL_M + 1e-9
    assert np.linalg.norm(recorded[-1] - live[-1]) <= VOXEL_M + 1e-9
    assert abs(len(recorded) - len(live)) <= 1
    assert np.linalg.norm(recorded[-1] - recorded[0]) > 0.1  # a real path, not a point


def test_colour_depth_is_the_default_on_frames(frames: Path, tmp_path: Path) -> None:
    code, summary = _run_frames(frames, tmp_path / "run")
    assert code == 0 and summary["perception"] == "colour-depth"
    assert {"blue block", "green block"} <= set(summary["scene"]["objects_seen"])


def test_only_the_first_subtask_is_planned(frames: Path, tmp_path: Path) -> None:
    twice = "go above the blue block twice"
    sub = "move to 8cm above the blue block while staying 10cm away from the green block"
    recordings = tmp_path / "twice.jsonl"
    recordings.write_text(RECORDINGS.read_text() + "\n" + json.dumps(
        {"lmp": "planner", "query": twice, "responses": [
            f"composer({sub!r})\nreset_to_default_pose()\ncomposer({sub!r})"]}) + "\n")
    code, summary = _run_frames(frames, tmp_path / "run", recordings=recordings,
                                instruction=twice)
    assert code == 0, summary["message"]
    assert [(s["subtask"], s["planned"]) for s in summary["subtasks"]] == [
        (sub, True), ("reset_to_default_pose()", False), (sub, False)]
    assert sorted(p.name for p in (tmp_path / "run").glob("subtask_*.html")) == [
        "subtask_01.html"]


def test_the_stub_robot_reports_the_recorded_pose_and_refuses_to_move(frames: Path) -> None:
    obs = load_frames(frames)
    robot = RecordedPoseRobot(obs)
    np.testing.assert_array_equal(robot.get_ee_pose()[0], obs.ee_position)
    assert robot.get_gripper_state() == obs.gripper and robot.time == obs.time
    for move in (lambda: robot.step(obs.ee_position, obs.ee_quat),
                 lambda: robot.move_to_pose(obs.ee_position), robot.close_gripper,
                 robot.reset_to_default_pose):
        with pytest.raises(NoRobotError, match="--robot none"):
            move()


@pytest.mark.parametrize(("argv", "words"), [
    (["--robot", "none"], ["--robot none", "--frames DIR"]),
    (["--frames", "{frames}"], ["--robot none"]),
    (["--frames", "{frames}", "--robot", "sim"], ["--robot none"]),
    (["--frames", "{frames}", "--robot", "none", "--disturb"], ["--disturb"]),
    (["--frames", "{missing}", "--robot", "none"], ["no frames folder", "absent"]),
    (["--frames", "{frames}", "--robot", "none", "--perception", "colour-depth-noisy"],
     ["colour-depth-noisy", "colour-depth or ground-truth"]),
    (["--frames", "{unlabelled}", "--robot", "none", "--perception", "ground-truth"],
     ["needs labels", "--with-labels"]),
    (["--register-cameras"], ["--register-cameras", "--frames DIR"]),
])
def test_bad_frame_options_are_one_clear_error(frames: Path, tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str],
                                               argv: list[str], words: list[str]) -> None:
    unlabelled = tmp_path / "unlabelled"
    if "{unlabelled}" in argv:
        assert _render(unlabelled) == 0
    paths = {"frames": str(frames), "missing": str(tmp_path / "absent"),
             "unlabelled": str(unlabelled)}
    capsys.readouterr()
    code = main(["run", MOVE_ABOVE_BLUE, "--llm", "replay", "--recordings", str(RECORDINGS),
                 "--out", str(tmp_path / "out"), *(a.format(**paths) for a in argv)])
    err = " ".join(capsys.readouterr().err.split())
    assert code == 2, err
    for word in words:
        assert word in err, err
    assert not (tmp_path / "out").exists()  # refused before anything ran


def test_with_labels_needs_save_frames(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["render", "--with-labels"]) == 2
    assert "--save-frames" in capsys.readouterr().err


def test_register_cameras_makes_miscalibrated_recorded_cameras_agree(
        frames: Path, tmp_path: Path) -> None:
    """Frames whose extrinsics carry a rig's calibration error, read with
    --register-cameras: the perceiver sees the cameras corrected towards each other."""
    import argparse

    from tests.calibration import disagreement_mm, miscalibrated
    from voxposer.cli.run_frames import frames_embodiment
    from voxposer.perception.frames import save_frames
    from voxposer.perception.view_registration import RegisteredObservationSource

    exact = load_frames(frames)
    off = miscalibrated(exact, 0)
    save_frames(off, tmp_path / "off")
    _, plain = frames_embodiment(tmp_path / "off", "colour-depth",
                                 argparse.Namespace(register_cameras=False))
    assert not isinstance(plain.perceiver.source, RegisteredObservationSource)
    _, body = frames_embodiment(tmp_path / "off", "colour-depth",
                                argparse.Namespace(register_cameras=True))
    source = body.perceiver.source
    assert isinstance(source, RegisteredObservationSource)
    body.perceiver.observe()
    before = disagreement_mm(exact, off)
    after = disagreement_mm(exact, off, source.corrections)
    assert before > 10.0 and after < 0.4 * before, f"{before:.1f} → {after:.1f} mm"
