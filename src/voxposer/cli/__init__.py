"""Command line: ``voxposer <command>``.

Commands:
    run         carry out an instruction in the simulated tabletop: LLM programs compose value
                maps, the planner and closed-loop executor move the robot; writes an MP4, HTML
                value maps, the LMP transcript and summary.json.
    plan-demo   plan through the built-in synthetic scene (global planner vs the paper's greedy
                one) and write an HTML picture of the cost map and both paths.
    lmp         try one language model program on the fixed tabletop scene; print its code and
                write the resulting map as HTML.
    bench       the 13-task simulated benchmark (paper Table 4) in parallel, with a report.
    render      render the four camera views of a seeded tabletop scene to one PNG.
    learn-dynamics
                learn a dynamics model online for the door, window and fridge, with zero-shot
                trajectories as exploration prior or without (paper Table 3).
    bench-data  training data of the U-Net + MP baseline (paper Table 2): observations,
                instructions and the reference programs' cost maps on dev seeds.
    train-unet  train the baseline's language-conditioned cost U-Net (needs the vision extra).

Every command checks its arguments before it starts any work (:mod:`voxposer.cli.checks`): a
bad value is one line naming it and what is allowed, and exit status 2.
"""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from voxposer.cli.checks import OneLineParser, check_out_dir, check_seed
from voxposer.errors import VoxPoserError

console = Console(stderr=True)


def _plan_demo(args: argparse.Namespace) -> int:
    import numpy as np

    from voxposer.planning import PathPlanner, PlannerConfig
    from voxposer.planning.picture import plan_figure, write_plan_html
    from voxposer.planning.synthetic_scene import make_synthetic_scene

    scene = make_synthetic_scene(np.random.default_rng(args.seed))
    maps: dict[str, Any] = {
        "avoidance_map": scene.avoidance_map,
        "rotation_map": scene.rotation_map,
        "velocity_map": scene.velocity_map,
        "gripper_map": scene.gripper_map,
        "occupancy": scene.occupancy,
    }
    with console.status("planning (first run compiles the search kernel)…"):
        plans = {
            method: PathPlanner(scene.grid, PlannerConfig(method=method)).plan(
                scene.affordance_map, scene.start, **maps
            )
            for method in ("global", "greedy")
        }
    table = Table(
        title=f"synthetic scene, seed {args.seed}: start {scene.start.tolist()} m → target "
        f"{np.round(scene.target, 3).tolist()} m"
    )
    for col in ("planner", "reached", "end error [cm]", "length [m]", "waypoints", "time [ms]"):
        table.add_column(col)
    for method, plan in plans.items():
        err = float(np.linalg.norm(plan.target - scene.target)) * 100
        table.add_row(
            method,
            "yes" if plan.reached else "no (stalled)",
            f"{err:.1f}",
            f"{plan.trajectory.length:.2f}",
            str(len(plan.trajectory)),
            f"{plan.timings_ms['total']:.1f}",
        )
    console.print(table)
    fig = plan_figure(
        plans["global"],
        scene.points,
        {"greedy (paper release)": plans["greedy"].trajectory.positions},
        title="VoxPoser synthetic scene: global planner vs greedy baseline",
    )
    out = write_plan_html(Path(args.out) / "plan.html", fig)
    console.print(f"wrote [bold]{out}[/bold]")
    return 0 if plans["global"].reached else 1


def _check_plan_demo(args: argparse.Namespace) -> None:
    check_seed(args.seed)
    check_out_dir(Path(args.out))


def build_parser() -> argparse.ArgumentParser:
    """The ``voxposer`` parser; each command sets ``func`` (the command) and ``check`` (its
    argument checks, run first)."""
    parser = OneLineParser(prog="voxposer", description=__doc__.splitlines()[0])
    parser.add_argument("-v", "--verbose", action="store_true", help="debug logging")
    sub = parser.add_subparsers(dest="command", required=True, metavar="command")
    demo = sub.add_parser(
        "plan-demo", help="plan through the built-in synthetic scene; write plan.html"
    )
    demo.add_argument("--seed", type=int, default=0, help="seed for the random obstacle blobs")
    demo.add_argument("--out", default="runs/plan-demo", help="output folder")
    demo.set_defaults(func=_plan_demo, check=_check_plan_demo)
    from voxposer.cli import (
        bench,
        bench_data,
        learn_dynamics,
        learn_push,
        lmp,
        render,
        run,
        train_unet,
    )

    run.add_parser(sub)
    bench.add_parser(sub)
    bench_data.add_parser(sub)
    train_unet.add_parser(sub)
    learn_dynamics.add_parser(sub)
    learn_push.add_parser(sub)
    lmp.add_parser(sub)
    render.add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``voxposer <argv>`` (default: the process's arguments); returns the exit status
    (2: a bad argument or a VoxPoserError before the command could finish)."""
    parser = build_parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # a usage error (one line, already printed) or --help
        return exc.code if isinstance(exc.code, int) else 2
    args.argv = argv  # what a command prints to be run again (voxposer bench: --resume)
    logging.basicConfig(level=logging.DEBUG if args.verbose else logging.WARNING)
    try:
        check = getattr(args, "check", None)
        if check is not None:
            check(args)
        return int(args.func(args))
    except VoxPoserError as err:
        console.print(f"[bold red]error:[/bold red] {escape(str(err))}", soft_wrap=True)
        return 2


if __name__ == "__main__":
    sys.exit(main())
