"""The work of ``voxposer learn-dynamics`` with a live progress bar per learning run."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from voxposer.learning.loop import LearnConfig, RunSpec, config_record, run_learning
from voxposer.learning.rollout import Episode
from voxposer.learning.zero_shot import ZeroShotTrajectory, load_trajectories

console = Console(stderr=True)


def make_world(task: str) -> tuple[Any, Any]:
    """The articulated world of ``task`` and its perception-based observer."""
    from voxposer.envs.articulated import ArticulatedWorld
    from voxposer.learning.state import StateObserver, layout_for
    from voxposer.perception.segmentation import SegmentationPerceiver

    world = ArticulatedWorld(task)
    perceiver = SegmentationPerceiver(world, world.grid)
    return world, StateObserver(layout_for(task), world, perceiver)


def record(tasks: tuple[str, ...], k: int, source: str, out: Path,
           period_s: float) -> None:
    """Record ``k`` zero-shot trajectories of each task into ``out/zero-shot/<task>/``."""
    from voxposer.learning.record import record_zero_shot
    from voxposer.learning.reference import INSTRUCTIONS, reference_backend
    from voxposer.lmp.backends.factory import make_backend

    for task in tasks:
        world, _ = make_world(task)
        backend = reference_backend(task) if source == "reference" else make_backend()
        name = "reference" if source == "reference" else backend.model
        folder = out / "zero-shot" / task
        with console.status(f"zero-shot {task} ({name})…") as status:
            for seed in range(k):
                if (folder / f"{name.replace('/', '_')}-{seed}.npz").exists():
                    continue
                status.update(f"zero-shot {task} ({name}): run {seed + 1}/{k}")
                traj = record_zero_shot(world, backend, INSTRUCTIONS[task], task=task,
                                        source=name, seed=seed, period_s=period_s)
                traj.save(folder)
                console.print(f"zero-shot {task} seed {seed}: "
                              f"{'opened' if traj.success else 'not opened'}, "
                              f"{len(traj.waypoints)} waypoints, {len(traj.stages)} sub-tasks")


def learn_all(tasks: tuple[str, ...], prior: str, seeds: int, config: LearnConfig,
              record_k: int, source: str, out: Path, argv: list[str]) -> int:
    """Record (``record_k`` > 0), learn every (task, arm, seed), write the report; exit 0."""
    from voxposer.learning.report import table3, write_curves

    time_limit = config.time_limit_s
    out.mkdir(parents=True, exist_ok=True)
    (out / "config.json").write_text(json.dumps(
        {"argv": argv, "config": config_record(config)}, indent=1, default=str))
    if record_k:
        record(tasks, record_k, source, out, config.rollout.step_duration_s)
    arms = {"on": (True,), "off": (False,), "both": (True, False)}[prior]
    all_records: list[dict[str, Any]] = []
    zero_shot: list[ZeroShotTrajectory] = []
    columns = (TextColumn("{task.description}"), BarColumn(),
               TextColumn("{task.completed:.0f}/{task.total:.0f} s simulated"),
               TimeElapsedColumn())
    with Progress(*columns, console=console) as bars:
        for task in tasks:
            trajectories = load_trajectories(out / "zero-shot" / task, task)
            zero_shot += trajectories
            for on in arms:
                for seed in range(seeds):
                    spec = RunSpec(task, on, seed)
                    bar = bars.add_task(_label(spec, {}), total=time_limit)

                    records = run_learning(spec, config, trajectories, make_world, out,
                                           _updater(bars, bar, time_limit))
                    all_records += records
                    last = records[-1]
                    bars.update(bar, completed=min(time_limit, last["interaction_s"]),
                                description=_label(spec, last, done=True))
    report = table3(all_records, zero_shot)
    (out / "table3.md").write_text(report)
    if any("eval_success" in r for r in all_records):
        write_curves(all_records, out / "learning_curves.png")
    console.print(report)
    return 0


def _updater(bars: Progress, bar: Any, time_limit: float) -> Any:
    """The progress callback of one run's bar: interaction time, iteration, last episode."""
    seen: dict[str, Any] = {"time": 0.0}

    def update(spec: RunSpec, iteration: int, kind: str, episode: Episode) -> None:
        if kind == "collect":
            seen["time"] += episode.sim_time_s
        seen.update(iteration=iteration, last=f"{kind} {'ok' if episode.success else 'no'}")
        bars.update(bar, completed=min(time_limit, seen["time"]), description=_label(spec, seen))

    return update


def _label(spec: RunSpec, state: dict[str, Any], done: bool = False) -> str:
    arm = "prior" if spec.prior else "no prior"
    head = f"{spec.task} {arm} seed {spec.seed}"
    if done:
        return (f"{head}: {state.get('stopped', '')}, eval "
                f"{100 * state.get('eval_success', 0.0):.0f}%, {state.get('transitions', 0)} "
                f"transitions, loss {state.get('loss', float('nan')):.3g}")
    if not state:
        return head
    return f"{head}: iteration {state['iteration']}, {state['last']}"


__all__ = ["learn_all", "make_world", "record"]
