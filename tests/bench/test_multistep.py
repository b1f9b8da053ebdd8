"""The multi-step suite without running episodes: its entries stay out of the 13-task registry,
every entry resets to a start where no step holds, a step that holds at reset is rejected, the
order check reads the trace (a step that holds before the one before it fails), and the runner,
CLI and report know the suite."""

from __future__ import annotations

import argparse
import math
from itertools import pairwise

import numpy as np
import pytest

from voxposer.bench import TASKS, BenchConfig, Tolerances, reset_episode
from voxposer.bench.multistep import ENTRIES, get_entry
from voxposer.bench.multistep.moves import AtPlace, AtPlaceKeepingAway, Hover
from voxposer.bench.multistep.objects import PushedTo
from voxposer.bench.multistep.order import judge_steps
from voxposer.bench.report_multistep import multistep_markdown
from voxposer.bench.task import ResetError, registered_tasks
from voxposer.bench.tasks._common import block_layout
from voxposer.bench.trace import Trace, snapshot
from voxposer.cli import bench as bench_cmd
from voxposer.errors import ConfigError
from voxposer.places import get_place

TOL = Tolerances()
JOINERS = (", then ", " and then ", ", and then ", ", after that ", "first ")


def _trace(ee: list, objects: dict | None = None, dt: float = 0.02) -> Trace:
    ee_arr = np.asarray(ee, dtype=float).reshape(-1, 3)
    objs = {k: np.broadcast_to(np.asarray(v, float), ee_arr.shape).copy() if np.ndim(v) == 1
            else np.asarray(v, float) for k, v in (objects or {}).items()}
    return Trace(np.arange(len(ee_arr)) * dt, ee_arr, np.zeros(len(ee_arr)), objs)


def _path(*points, n: int = 20) -> list:
    out: list = []
    for a, b in pairwise(points):
        out += list(np.linspace(np.asarray(a, float), np.asarray(b, float), n))
    return out


def test_entries_stay_out_of_the_task_registry() -> None:
    assert 8 <= len(ENTRIES) <= 10
    assert len(TASKS) == 13  # (other test modules may register tasks of their own)
    assert not set(ENTRIES) & set(registered_tasks())
    for name, entry in ENTRIES.items():
        steps = entry.steps(entry.sample_attributes(np.random.default_rng(0), "seen"))
        assert 2 <= len(steps) <= 3, name
        assert any(j in entry.template for j in JOINERS), entry.template
    with pytest.raises(ConfigError, match="hover_then_region"):
        get_entry("push_to_pos")


@pytest.mark.parametrize("name", list(ENTRIES))
def test_reset_leaves_every_step_to_do(world, name: str) -> None:
    entry = get_entry(name)
    setup = reset_episode(entry, world, "seen", 0)
    trace = snapshot(world, entry.tracked(setup.attributes))
    for step in entry.steps(setup.attributes):
        assert not step.held(world, trace, TOL)[0], step.label
    ref = {(e["lmp"], e["query"]): e["responses"][0] for e in
           entry.reference(setup.attributes).entries()}
    wrong = {(e["lmp"], e["query"]): e["responses"][0] for e in
             entry.wrong_order(setup.attributes).entries()}
    plan = ref[("planner", setup.instruction)].splitlines()
    assert len(plan) >= 2 and all(line.startswith("composer(") for line in plan)
    assert wrong[("planner", setup.instruction)] != ref[("planner", setup.instruction)]
    assert sorted(wrong[("planner", setup.instruction)].splitlines()) == sorted(plan)


def test_a_step_that_holds_at_reset_is_rejected(world, monkeypatch) -> None:
    entry = get_entry("push_then_away")
    setup = reset_episode(entry, world, "seen", 0)
    obj = setup.attributes["obj"]
    xy = tuple(world.object_position(obj)[:2])
    # the same block, but the end effector at its rest pose: already "away from it"
    monkeypatch.setattr(entry, "layout", lambda rng, attrs: block_layout(
        {obj: xy}, extra_blocks=(0, 0), extra_lines=(0, 0)))
    world.reset(np.random.default_rng(0), entry.layout(None, setup.attributes))
    problem = entry.reset_problem(world, setup.attributes, TOL)
    assert problem is not None and "step 2" in problem and "already holds at reset" in problem
    with pytest.raises(ResetError, match="already holds at reset"):
        reset_episode(entry, world, "seen", 0)


def test_the_order_check_reads_the_trace() -> None:
    block = np.array([-0.1, -0.2, 0.025])
    region = get_place("right side of the table").point
    hover = block + [0.0, 0.0, 0.15]
    steps = (Hover("blue block"), AtPlace("right side of the table"))
    start = (-0.23, 0.0, 0.47)
    objects = {"blue block": block}
    good = judge_steps(steps, None, _trace(_path(start, hover, (*region, 0.05)), objects), TOL)
    assert good.success, good.reason
    assert good.metrics["step1_ok"] == good.metrics["step2_ok"] == 1.0
    assert 0 < good.metrics["step1_t"] < good.metrics["step2_t"]
    # step 2 (the region) holds first, then step 1 (the hover): out of order
    swapped = judge_steps(steps, None, _trace(_path(start, (*region, 0.05), hover), objects), TOL)
    assert not swapped.success
    assert "out of order" in swapped.reason and "step 2" in swapped.reason
    assert swapped.metrics["step1_held"] == swapped.metrics["step2_held"] == 1.0
    assert swapped.metrics["step1_ok"] == 1.0 and swapped.metrics["step2_ok"] == 0.0
    assert swapped.metrics["in_order"] == 0.0
    # step 1 never held: the reason names it
    never = judge_steps(steps, None, _trace(_path(start, (*region, 0.05)), objects), TOL)
    assert not never.success and never.reason.startswith("step 1 (hover 10cm over the blue")
    assert never.metrics["step1_t"] == -1.0


def test_object_states_must_persist_and_clauses_hold_over_their_step() -> None:
    place = get_place("back side of the table")
    start, at = np.array([-0.1, 0.0, 0.025]), np.array([place.point[0], 0.0, 0.025])
    block = np.array(_path(start, at, at, start))  # pushed there, then knocked back out
    ee = np.array(_path((-0.2, 0.0, 0.2), (-0.4, 0.0, 0.2), (-0.3, 0.0, 0.3), (0.0, 0.0, 0.3)))
    steps = (PushedTo("blue block", place.name), Hover("blue block"))
    v = judge_steps(steps, None, _trace(ee, {"blue block": block}), TOL)
    assert not v.success and "no longer at the end" in v.reason
    # an object state done before the step asked first: out of order, though it still holds
    hover_then_push = (Hover("blue block"), PushedTo("blue block", place.name))
    pushed = np.array(_path(start, at, at, at))
    ee = np.array(_path((-0.2, 0.0, 0.2), (-0.4, 0.0, 0.2), (-0.4, 0.0, 0.3), at + [0, 0, 0.15]))
    v = judge_steps(hover_then_push, None, _trace(ee, {"blue block": pushed}), TOL)
    assert not v.success and v.reason.startswith("out of order: step 2 (push the blue block")
    assert v.metrics["step2_held"] == 1.0 and v.metrics["in_order"] == 0.0
    # "while staying at least 5cm from the blue block": the path grazes it
    obstacle = np.array([-0.30, 0.0, 0.025])
    keep = (AtPlaceKeepingAway(place.name, "blue block", 5), Hover("blue block"))
    grazing = _path((-0.2, 0.0, 0.06), (-0.30, 0.0, 0.06), (*place.point, 0.05),
                    obstacle + [0.0, 0.0, 0.15])
    v = judge_steps(keep, None, _trace(grazing, {"blue block": obstacle}), TOL)
    assert not v.success and "broke its constraint" in v.reason and "step 1" in v.reason


def test_runner_and_cli_know_the_suite() -> None:
    cfg = BenchConfig(suite="multistep", episodes=1, splits=("seen",))
    assert cfg.tasks == tuple(ENTRIES)
    assert {j.suite for j in cfg.jobs()} == {"multistep"} and len(cfg.jobs()) == len(ENTRIES)
    assert {j.suite for j in BenchConfig(episodes=1).jobs()} == {"tasks"}
    with pytest.raises(ConfigError, match="hover_then_region"):
        BenchConfig(suite="multistep", tasks=("push_to_pos",))
    with pytest.raises(ConfigError, match="tasks, multistep"):
        BenchConfig(suite="everything")
    with pytest.raises(ConfigError, match="seen"):
        BenchConfig(suite="multistep", llm="default", instructions="unseen")

    def args(*argv: str) -> argparse.Namespace:
        parser = argparse.ArgumentParser()
        bench_cmd.add_parser(parser.add_subparsers())
        return parser.parse_args(["bench", *argv])

    cfg = bench_cmd._config(args("--suite", "multistep", "--tasks", "push_then_away",
                                 "--seeds", "test", "--episodes", "2"))
    assert cfg.tasks == ("push_then_away",) and list(cfg.seed_list()) == [100_000, 100_001]
    assert bench_cmd._default_out(cfg) == "voxposer-default-multistep-test"
    with pytest.raises(ConfigError, match="grasp_then_drop"):
        bench_cmd._config(args("--suite", "multistep", "--tasks", "move_to_region"))
    assert bench_cmd._config(args()).tasks == tuple(TASKS)


def test_report_gives_entries_steps_and_the_fraction() -> None:
    def rec(task: str, seed: int, oks: list[bool]) -> dict:
        metrics = {f"step{k}_ok": float(ok) for k, ok in enumerate(oks, 1)}
        return {"task": task, "split": "seen", "seed": seed, "method": "voxposer",
                "llm": "reference", "suite": "multistep", "success": all(oks),
                "reason": "ok" if all(oks) else "out of order: step 2", "metrics": metrics,
                "code_hash": "abc", "timings_s": {}, "llm_calls": 3}

    records = [rec("hover_then_region", 0, [True, True]), rec("hover_then_region", 1, [True, False]),
               rec("push_hover_region", 0, [True, True, True])]
    text = multistep_markdown(records)
    assert "| hover_then_region |" in text and "50.0% (1/2)" in text
    assert "step 1 100.0% (3/3), step 2 66.7% (2/3), step 3 100.0% (1/1)" in text
    assert "out of order: step 2" in text
    last = text.strip().splitlines()[-1]
    assert last == "fully_completed=0.667 episodes=3 entries=2"
    assert math.isclose(float(last.split()[0].split("=")[1]), 2 / 3, abs_tol=1e-3)
