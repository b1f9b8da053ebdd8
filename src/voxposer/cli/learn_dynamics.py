"""``voxposer learn-dynamics``: online dynamics learning on the door, window and fridge (Table 3).

First (``--record-zero-shot K``) VoxPoser opens each object zero-shot K times and keeps each
run's end-effector trajectory τ₀ and value maps under ``<out>/zero-shot/<task>/``. Then for every
task, arm (``--prior on|off|both``) and seed an MLP dynamics model is learned online until the
evaluation succeeds or ``--time-limit`` seconds of simulated interaction are spent. Runs write
as they go and continue where they stopped when started again with the same ``--out``. The
output holds ``table3.md`` (beside the paper's numbers) and ``learning_curves.png``.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import replace
from pathlib import Path
from typing import Any, Final

from voxposer.cli.checks import check_int, check_out_dir
from voxposer.errors import ConfigError

TASKS: Final = ("door", "window", "fridge")
PRIORS: Final = ("on", "off", "both")
ZERO_SHOT_SOURCES: Final = ("reference", "default")


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register ``learn-dynamics`` on an ``argparse`` sub-parsers object."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "learn-dynamics", help="learn a dynamics model online with zero-shot trajectories as "
        "exploration prior (door, window, fridge; paper Table 3)")
    p.add_argument("--task", default="door",
                   help=f"one of {', '.join(TASKS)}, a comma-separated list, or 'all'")
    p.add_argument("--prior", default="both", help=f"one of {', '.join(PRIORS)}")
    p.add_argument("--seeds", type=int, default=3, help="learning runs per task and arm")
    p.add_argument("--time-limit", type=float, default=180.0,
                   help="simulated interaction per run [s] (default 180: the paper's 3 minutes)")
    p.add_argument("--noise-cm", type=float, default=None,
                   help="σ of the exploration noise ε on each of τ₀'s waypoints, and of the "
                   "MPC's samples around it [cm] (default: LearnConfig.sigma_m)")
    p.add_argument("--record-zero-shot", type=int, default=0, metavar="K",
                   help="first record K zero-shot trajectories per task (default: use those "
                   "already in <out>/zero-shot)")
    p.add_argument("--zero-shot-llm", default="reference",
                   help=f"who writes the zero-shot programs: {', '.join(ZERO_SHOT_SOURCES)} "
                   "(the bundled model)")
    p.add_argument("--out", type=Path, default=Path("runs/learn-dynamics"), help="output folder")
    p.set_defaults(func=run, check=check_args)
    return p


def selected_tasks(value: str) -> tuple[str, ...]:
    """The tasks ``--task`` names; ConfigError listing the known ones."""
    names = TASKS if value == "all" else tuple(v.strip() for v in value.split(",") if v.strip())
    bad = [n for n in names if n not in TASKS]
    if bad or not names:
        raise ConfigError(f"unknown --task {', '.join(bad) or value!r}; tasks are: "
                          f"{', '.join(TASKS)} (or 'all')")
    return names


def check_args(args: argparse.Namespace) -> None:
    """Every bad value is refused before any work starts: task, prior, seeds, time limit, the
    zero-shot source, and a missing zero-shot trajectory."""
    tasks = selected_tasks(args.task)
    if args.prior not in PRIORS:
        raise ConfigError(f"unknown --prior {args.prior!r}; choose one of: {', '.join(PRIORS)}")
    check_int(args.seeds, "--seeds", 1)
    if not args.time_limit > 0:
        raise ConfigError(f"--time-limit must be > 0 seconds, got {args.time_limit!r}")
    if args.noise_cm is not None and not (math.isfinite(args.noise_cm) and args.noise_cm > 0):
        raise ConfigError(f"--noise-cm must be a number of centimetres > 0, got {args.noise_cm!r}")
    check_int(args.record_zero_shot, "--record-zero-shot", 0)
    if args.zero_shot_llm not in ZERO_SHOT_SOURCES:
        raise ConfigError(f"unknown --zero-shot-llm {args.zero_shot_llm!r}; choose one of: "
                          f"{', '.join(ZERO_SHOT_SOURCES)}")
    check_out_dir(args.out)
    if args.record_zero_shot == 0:
        for task in tasks:
            folder = args.out / "zero-shot" / task
            if not any(folder.glob("*.npz")):
                raise ConfigError(
                    f"no zero-shot trajectory of {task!r} in {folder}: the task cost (and the "
                    "prior) come from them; add --record-zero-shot K")


def run(args: argparse.Namespace) -> int:
    """Record (if asked), learn every run, write the table and the curves; exit status."""
    from voxposer.cli.learn_progress import learn_all
    from voxposer.learning.loop import LearnConfig

    config = LearnConfig(time_limit_s=args.time_limit)
    if args.noise_cm is not None:
        config = replace(config, sigma_m=args.noise_cm / 100.0)
    return learn_all(selected_tasks(args.task), args.prior, args.seeds, config,
                     args.record_zero_shot, args.zero_shot_llm, args.out, args.argv)


__all__ = ["PRIORS", "TASKS", "add_parser", "check_args", "selected_tasks"]
