"""``voxposer bench-data``: training data of the "U-Net + MP" baseline (paper Table 2).

For every task and dev seed: reset as the benchmark does (seen attributes and instruction), run
the reference programs up to the executor's first plan, and keep (observation voxels,
instruction, the planner's cost map of the first sub-task) — see :mod:`voxposer.bench.unet_data`.
Writes compressed shards and ``manifest.json`` to ``--out``; ``--resume`` adds only the
(task, seed) pairs not yet there. ``--seeds dev`` takes the first ``--episodes`` dev seeds; a
list such as ``0,5,10-19`` names them (dev seeds only: test seeds are never trained on).

Example::

    voxposer bench-data --out runs/unet-data --episodes 50 --seeds dev
    voxposer bench-data --out runs/unet-data --episodes 100 --seeds dev --resume
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from voxposer.cli.checks import check_int, check_out_dir
from voxposer.errors import ConfigError

console = Console(stderr=True)


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register ``bench-data`` on an ``argparse`` sub-parsers object."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "bench-data", help="training data for the U-Net + MP baseline: observations, "
        "instructions and the reference programs' cost maps on dev seeds")
    p.add_argument("--out", type=Path, required=True, help="the dataset folder")
    p.add_argument("--episodes", type=int, default=20, help="seeds per task (default 20)")
    p.add_argument("--seeds", default="dev",
                   help="'dev' (its first --episodes seeds) or a list like '0,5,10-19'")
    p.add_argument("--tasks", default="all", help="comma-separated task names, or 'all'")
    p.add_argument("--shard-size", type=int, default=32, help="samples per shard file")
    p.add_argument("--resume", action="store_true",
                   help="add to an existing dataset (its done seeds are skipped)")
    p.set_defaults(func=run, check=check_args)
    return p


def selected_tasks(value: str) -> tuple[str, ...]:
    """The tasks ``--tasks`` names; ConfigError listing the known ones."""
    from voxposer.bench.tasks import TASKS

    if value.strip() == "all":
        return tuple(TASKS)
    names = tuple(v.strip() for v in value.split(",") if v.strip())
    bad = [n for n in names if n not in TASKS]
    if bad or not names:
        raise ConfigError(f"unknown --tasks {', '.join(bad) or repr(value)}; tasks are: "
                          f"{', '.join(TASKS)} (or 'all')")
    return names


def check_args(args: argparse.Namespace) -> None:
    """Refuse bad values before any work: episodes, seeds (dev only), tasks, shard size, and an
    existing dataset without ``--resume``."""
    from voxposer.bench.unet_data import parse_seeds
    from voxposer.unet.dataset import MANIFEST

    check_int(args.episodes, "--episodes", 1)
    check_int(args.shard_size, "--shard-size", 1)
    parse_seeds(args.seeds, args.episodes)
    selected_tasks(args.tasks)
    check_out_dir(args.out)
    if (args.out / MANIFEST).exists() and not args.resume:
        raise ConfigError(f"{args.out} already holds a dataset; add --resume to add to it")


def run(args: argparse.Namespace) -> int:
    """Generate with a progress bar; print where it went and how long it took."""
    from voxposer.bench.unet_data import DataConfig, generate, parse_seeds
    from voxposer.envs import TabletopWorld

    config = DataConfig(selected_tasks(args.tasks), tuple(parse_seeds(args.seeds, args.episodes)),
                        args.shard_size)
    total = len(config.tasks) * len(config.seeds)
    world = TabletopWorld()
    counts = {"ok": 0, "skipped": 0}
    start = time.perf_counter()
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
               TimeElapsedColumn())
    try:
        with Progress(*columns, console=console) as bars:
            bar = bars.add_task("bench-data", total=total)

            def update(task: str, seed: int, what: str) -> None:
                counts["ok" if what == "ok" else "skipped"] += 1
                bars.update(bar, advance=1, description=f"{task} seed {seed}: {what[:40]}")

            manifest = generate(args.out, world, config, resume=args.resume, on_episode=update)
    finally:
        world.close()
    new = counts["ok"] + counts["skipped"]
    per = (time.perf_counter() - start) / new if new else 0.0
    samples = sum(s["count"] for s in manifest["shards"])
    console.print(f"{counts['ok']} new samples ({counts['skipped']} skipped, "
                  f"{total - new} already done), {per:.2f} s per episode; {samples} samples in "
                  f"{len(manifest['shards'])} shards, grid {manifest['grid_shape']}: "
                  f"[bold]{args.out}[/bold]")
    return 0


__all__ = ["add_parser", "check_args", "selected_tasks"]
