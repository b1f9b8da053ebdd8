"""``voxposer bench --breakdown RUN [RUN …]``: the error breakdown of benchmark runs (Fig. 4).

Every failed episode of each run folder is re-run with its components replaced by their ground
truth (:mod:`voxposer.bench.breakdown`); attributions go to ``<run>/breakdown.jsonl`` as they
finish (a second call continues), the table and the stacked bar chart of all the runs given to
``--out`` (default ``runs/breakdown``): ``breakdown.md``, ``breakdown.png``.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from voxposer.bench.breakdown_run import RunBreakdown, break_down, load_run, pending
from voxposer.bench.report_breakdown import write_breakdown
from voxposer.cli.interrupts import stop_signals

console = Console(stderr=True)
#: where the combined report goes without ``--out``.
DEFAULT_OUT = Path("runs") / "breakdown"


def _runs(args: argparse.Namespace) -> list[RunBreakdown]:
    tasks = None if args.tasks.strip() == "all" else tuple(
        t.strip() for t in args.tasks.split(",") if t.strip())
    return [load_run(Path(folder), tasks) for folder in args.breakdown]


def check_breakdown(args: argparse.Namespace) -> None:
    """Refuse, before any re-run, a folder without results or a failure that cannot be re-run
    (ConfigError naming the folder or what the episode lacks)."""
    for run in _runs(args):
        pending(run)


def run_breakdown(args: argparse.Namespace) -> int:
    """Attribute the runs' failures, then write the report; exit status 0 when done."""
    from voxposer.envs import TabletopWorld

    runs = _runs(args)
    out = args.out or DEFAULT_OUT
    progress = Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                        MofNCompleteColumn(), TextColumn("{task.fields[tally]}"),
                        TimeElapsedColumn(), console=console)
    bar = progress.add_task("breakdown", total=None, tally="")
    tally: dict[str, int] = {}

    def on_start(todo: int) -> None:
        progress.update(bar, total=todo)
        done = sum(len(r.attributions) for r in runs)
        if done:
            console.print(f"continuing: {done} failures already attributed")

    def on_attribution(a: dict[str, Any]) -> None:
        tally[a["cause"]] = tally.get(a["cause"], 0) + 1
        progress.update(bar, advance=1, description=f"{a['task']} ({a['split']}, {a['seed']})",
                        tally=", ".join(f"{k} {v}" for k, v in sorted(tally.items())))

    world = TabletopWorld()
    with progress, stop_signals():
        try:
            runs = break_down(runs, world, on_start=on_start, on_attribution=on_attribution)
        except KeyboardInterrupt:
            console.print("[bold red]stopped[/]: the attributions so far are kept; run the same "
                          "command again to continue")
            runs = _runs(args)
            write_breakdown([r for run in runs for r in run.records],
                            [a for run in runs for a in run.attributions], out,
                            plot=not args.no_plot)
            return 130
    report = write_breakdown([r for run in runs for r in run.records],
                             [a for run in runs for a in run.attributions], out,
                             plot=not args.no_plot)
    console.print(report.read_text(encoding="utf-8").split("## Every failure")[0],
                  markup=False, highlight=False)
    console.print(f"wrote [bold]{report}[/]" + ("" if args.no_plot else
                                                 f", [bold]{out / 'breakdown.png'}[/]"))
    return 0


__all__ = ["check_breakdown", "run_breakdown"]
