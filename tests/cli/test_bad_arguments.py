"""Bad command-line values are refused before any work starts: one line naming the value and
what is allowed, exit status 2, and no simulator, model or benchmark worker started."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import voxposer.cli as cli
import voxposer.envs
from voxposer.cli import bench, lmp, render, run
from voxposer.lmp.backends import factory


def _never(*args: object, **kwargs: object) -> None:
    raise AssertionError("a command started work despite a bad argument")


@pytest.fixture(autouse=True)
def no_work(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every command's work, the world and the LLM backends fail the test if reached."""
    monkeypatch.setattr(run, "_rollout", _never)
    monkeypatch.setattr(bench, "run_bench", _never)
    monkeypatch.setattr(cli, "_plan_demo", _never)
    monkeypatch.setattr(lmp, "run", _never)
    monkeypatch.setattr(render, "run", _never)
    monkeypatch.setattr(voxposer.envs, "TabletopWorld", _never)
    monkeypatch.setattr(factory, "make_backend", _never)


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str], tmp_path: Path) -> str:
    """Run ``voxposer <argv>`` (output in ``tmp_path``); the one line it printed."""
    out = ["--out", str(tmp_path / "out")] if argv[0] in ("run", "bench") else []
    assert cli.main([*argv, *out]) == 2
    captured = capsys.readouterr()
    lines = [ln for ln in (captured.err + captured.out).splitlines() if ln.strip()]
    assert len(lines) == 1, lines
    assert lines[0].count("error") == 1, lines[0]
    assert not (tmp_path / "out").exists()
    return lines[0]


@pytest.mark.parametrize("argv, words", [
    (["run", ""], ["instruction is empty", "''", "e.g. 'push the blue block"]),
    (["run", "   \t"], ["instruction is only whitespace", "'   \\t'"]),
    (["run", "push the blue block left", "--seed", "-5"], ["--seed", ">= 0", "got -5"]),
    (["run", "push the blue block left", "--max-time", "0"], ["--max-time", "> 0", "got 0"]),
    (["run", "push the blue block left", "--max-time", "-3"], ["--max-time", "got -3"]),
    (["run", "push the blue block left", "--max-time", "inf"], ["--max-time", "finite"]),
    (["run", "push the blue block left", "--camera-hz", "0"], ["--camera-hz", "> 0", "got 0.0"]),
    (["run", "push the blue block left", "--camera-hz", "nan"], ["--camera-hz", "got nan"]),
    (["run", "push the blue block left", "--seed", "abc"], ["--seed", "'abc'", "int"]),
    (["run", "push the blue block left", "--llm", "replay"], ["recordings", "--recordings"]),
    (["run", "push the blue block left", "--llm", "gpt-17"], ["--llm", "'gpt-17'", "replay"]),
    (["run", "push the blue block left", "--base-url", "localhost:8080"],
     ["--base-url", "'localhost:8080'", "http://"]),
    (["run", "push the blue block left", "--place", "blue block=0.5,0"],
     ["--place", "'blue block=0.5,0'", "[-0.675, 0.275]"]),
    (["bench", "--episodes", "0"], ["--episodes", ">= 1", "got 0"]),
    (["bench", "--episodes", "-2"], ["--episodes", "got -2"]),
    (["bench", "--workers", "0"], ["--workers", "[1, ", "got 0"]),
    (["bench", "--workers", "100000"], ["--workers", "got 100000"]),
    (["bench", "--seed", "-5"], ["--seed", ">= 0", "got -5"]),
    (["bench", "--max-time", "0"], ["--max-time", "> 0", "got 0"]),
    (["bench", "--max-time", "nan"], ["--max-time", "got nan"]),
    (["bench", "--tasks", " , "], ["--tasks", "names nothing", "move_to_region"]),
    (["bench", "--tasks", "push_to_pos,push_to_pos"], ["--tasks", "'push_to_pos'", "once"]),
    (["bench", "--tasks", "fly_to_moon"], ["'fly_to_moon'", "move_to_region"]),
    (["bench", "--splits", "seen,nope"], ["'nope'", "seen, unseen"]),
    (["bench", "--seeds", "final"], ["'final'", "dev", "test"]),
    (["bench", "--seeds", "dev", "--seed", "3"], ["seeds='dev'", "seed=3", "not both"]),
    (["bench", "--episodes", "10001"], ["10000 seeds", "episodes=10001"]),
    (["bench", "--ray-address", "10.0.0.1:6379"], ["--ray-address", "--pool ray"]),
    (["bench", "--video", "sometimes"], ["'sometimes'", "failures"]),
    (["bench", "--llm", "openai"], ["model", "--model"]),
    (["bench", "--method", "unet_mp"], ["--method unet_mp needs --unet-checkpoint PATH"]),
    (["bench", "--unet-checkpoint", "m.pt"], ["--unet-checkpoint", "unet_mp only", "voxposer"]),
    (["bench", "--method", "unet_mp", "--unet-checkpoint", "/nonexistent/m.pt"],
     ["no U-Net checkpoint at /nonexistent/m.pt"]),
    (["bench", "--method", "unet_mp", "--unet-checkpoint", "m.pt", "--llm", "reference"],
     ["unet_mp runs no LLM", "--llm reference"]),
    (["bench", "--dynamics", "magic"], ["'magic'", "heuristic, simulator, learned"]),
    (["bench", "--dynamics", "learned"], ["--dynamics learned needs --push-model PATH"]),
    (["bench", "--push-model", "m.npz"], ["--push-model 'm.npz'", "--dynamics learned only"]),
    (["bench", "--dynamics", "learned", "--push-model", "/nonexistent/m.npz"],
     ["no push model at /nonexistent/m.npz"]),
    (["learn-push", "--out", "/nonexistent-learn-push", "--pushes", "3"],
     ["--pushes", ">= 16", "got 3"]),
    (["bench", "--breakdown", "/nonexistent/run"],
     ["--breakdown /nonexistent/run", "no episodes.jsonl"]),
    (["plan-demo", "--seed", "-5"], ["--seed", ">= 0", "got -5"]),
    (["lmp", " "], ["query is only whitespace"]),
    (["lmp", "a point above the blue block", "--max-attempts", "0"],
     ["--max-attempts", "[1, 10]", "got 0"]),
    (["render", "--seed", "-1"], ["--seed", "got -1"]),
    (["render", "--width", "0"], ["--width", "[1, 4096]", "got 0"]),
])
def test_a_bad_value_is_one_line_and_status_2(argv: list[str], words: list[str],
                                               capsys: pytest.CaptureFixture[str],
                                               tmp_path: Path) -> None:
    line = _refused(argv, capsys, tmp_path)
    assert all(w in line for w in words), line


def test_a_breakdown_of_episodes_without_their_programs_is_refused(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    run_dir = tmp_path / "old-run"
    run_dir.mkdir()
    old = {"task": "push_to_pos", "split": "seen", "seed": 7, "method": "voxposer",
           "llm": "default", "instructions": "seen", "success": False}  # written before programs
    (run_dir / "episodes.jsonl").write_text(json.dumps(old) + "\n")
    line = _refused(["bench", "--breakdown", str(run_dir)], capsys, tmp_path)
    assert "push_to_pos/seen/seed 7" in line and "lacks 'programs'" in line, line


def test_an_out_folder_that_is_a_file_is_refused(capsys: pytest.CaptureFixture[str],
                                                 tmp_path: Path) -> None:
    taken = tmp_path / "taken"
    taken.write_text("not a folder")
    for argv in (["run", "push the blue block left"], ["bench"], ["plan-demo"]):
        assert cli.main([*argv, "--out", str(taken)]) == 2
        err = capsys.readouterr().err
        assert f"--out '{taken}' is a file" in " ".join(err.split())


def test_good_values_reach_the_command(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """The checks pass what the commands accept (the stubbed command is reached)."""
    reached: list[str] = []
    monkeypatch.setattr(cli, "_plan_demo", lambda args: reached.append("plan-demo") or 0)
    monkeypatch.setattr(render, "run", lambda args: reached.append("render") or 0)
    assert cli.main(["plan-demo", "--seed", "0", "--out", str(tmp_path)]) == 0
    assert cli.main(["render", "--seed", "3", "--width", "320", "--height", "240"]) == 0
    assert reached == ["plan-demo", "render"]
    args = cli.build_parser().parse_args(["bench", "--llm", "reference", "--tasks",
                                          "move_to_region", "--episodes", "2", "--workers", "1",
                                          "--seed", "0", "--max-time", "0.5"])
    bench.check_args(args)  # no error
    args = cli.build_parser().parse_args(["run", "push the blue block left", "--llm", "replay",
                                          "--recordings", str(tmp_path / "r.jsonl"),
                                          "--seed", "7", "--max-time", "12.5"])
    run.check_args(args)  # a missing recordings file is the run's failure, not the CLI's
