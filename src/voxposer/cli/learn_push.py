"""``voxposer learn-push``: learn the pushing dynamics from simulated pushes (an MLP in the
push's frame, :mod:`voxposer.planning.dynamics.learned_push`), for ``voxposer bench --dynamics
learned``.

Pushes are sampled as the pushing MPC samples them and played in a copy of the world
(:mod:`voxposer.bench.push_data`); a held-out set from other scenes measures the learned model
beside the paper's heuristic. Writes to ``--out``: ``push_model.npz`` (the model),
``transitions.npz`` (training pushes, reused on a second call) and ``report.json``; the last line
printed is machine-readable.

Example::

    voxposer learn-push --out runs/push-model --pushes 2000
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from voxposer.cli.checks import check_int, check_out_dir

console = Console(stderr=True)
#: the model file ``--push-model`` of ``voxposer bench`` reads.
MODEL_FILE = "push_model.npz"


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register ``learn-push`` on an ``argparse`` sub-parsers object."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "learn-push", help="learn the pushing dynamics (an MLP) from simulated pushes")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--pushes", type=int, default=2000, help="training pushes (default 2000)")
    p.add_argument("--held-out", type=int, default=400, help="evaluation pushes (default 400)")
    p.add_argument("--epochs", type=int, default=300, help="training passes (default 300)")
    p.add_argument("--seed", type=int, default=0, help="seed of scenes, pushes and weights")
    p.set_defaults(func=run, check=check_args)
    return p


def check_args(args: argparse.Namespace) -> None:
    """Refuse bad numbers and an output path that is a file, before any work."""
    check_int(args.pushes, "--pushes", 16)
    check_int(args.held_out, "--held-out", 16)
    check_int(args.epochs, "--epochs", 1)
    check_int(args.seed, "--seed", 0)
    check_out_dir(args.out)


def _collect(world: Any, n: int, seed: int, label: str, bars: Progress) -> Any:
    from voxposer.bench.push_data import collect_pushes

    bar = bars.add_task(label, total=n)
    return collect_pushes(world, n, np.random.default_rng([seed, len(label)]),
                          on_scene=lambda done: bars.update(bar, completed=done))


def run(args: argparse.Namespace) -> int:
    """Collect (or reuse) the pushes, train, evaluate, write the model and report."""
    from voxposer.bench.push_data import fit_push_model, heuristic_errors, push_errors
    from voxposer.envs import TabletopWorld
    from voxposer.planning.dynamics.training import Transitions

    args.out.mkdir(parents=True, exist_ok=True)
    world = TabletopWorld()
    cached = args.out / "transitions.npz"
    start = time.perf_counter()
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
               TimeElapsedColumn())
    with Progress(*columns, console=console) as bars:
        train_set = Transitions.load(cached) if cached.is_file() else None
        if train_set is None or len(train_set) != args.pushes:
            train_set = _collect(world, args.pushes, args.seed, "training pushes", bars)
            train_set.save(cached)
        held = _collect(world, args.held_out, args.seed + 1, "held-out pushes", bars)
    collected = time.perf_counter() - start
    model = fit_push_model(train_set, np.random.default_rng(args.seed), epochs=args.epochs)
    model.model.save(args.out / MODEL_FILE)
    report = {"pushes": len(train_set), "held_out": len(held), "epochs": args.epochs,
              "collect_s": round(collected, 1),
              "train_s": round(time.perf_counter() - start - collected, 1),
              "learned": push_errors(model, held), "heuristic": heuristic_errors(held)}
    (args.out / "report.json").write_text(json.dumps(report, indent=2) + "\n", encoding="utf-8")
    for name in ("learned", "heuristic"):
        e = report[name]
        console.print(f"{name}: centre error median {e['centre_median_m'] * 100:.2f} cm, p90 "
                      f"{e['centre_p90_m'] * 100:.2f} cm; yaw error median "
                      f"{e['yaw_median_deg']:.1f}°, p90 {e['yaw_p90_deg']:.1f}°")
    console.print(f"wrote [bold]{args.out / MODEL_FILE}[/bold], {args.out / 'report.json'}")
    le, he = report["learned"], report["heuristic"]
    print(f"pushes={len(train_set)} learned_centre_median_cm={le['centre_median_m'] * 100:.3f} "
          f"heuristic_centre_median_cm={he['centre_median_m'] * 100:.3f} "
          f"learned_yaw_median_deg={le['yaw_median_deg']:.2f} "
          f"heuristic_yaw_median_deg={he['yaw_median_deg']:.2f}")
    return 0


__all__ = ["MODEL_FILE", "add_parser", "check_args"]
