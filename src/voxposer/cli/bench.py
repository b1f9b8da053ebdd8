"""``voxposer bench``: the paper's 13-task simulated benchmark (Table 4), in parallel.

Writes to ``--out``: ``episodes.jsonl`` (one record per episode, appended as each finishes),
``report.md`` (Table 4 layout beside the paper, Table 2-style aggregates, tolerances) and
``success.png``. ``--llm reference`` runs hand-written reference programs instead of an LLM —
it measures perception, planning, control and the checks, never the language model, and every
report says so; ``--llm reference-blind`` runs their constraint-blind control (tasks without a
constraint are skipped). ``--seeds dev|test`` picks the seed set (``voxposer.bench.protocol``),
``--instructions unseen`` holds each task's few-shot examples out of the prompts, and
``--fresh-cache`` answers from an empty response cache in ``<out>/cache/``. ``--video
failures|all`` records an MP4 per failed (or every) episode into ``<out>/videos/``, linked from
the report's failure modes; ``--disturb`` runs the episodes with the paper's disturbances
(Table 1; their records are ``disturbed`` and may share a file with static ones, and the report
puts both side by side). ``--suite multistep`` runs the multi-step instructions instead
(:mod:`voxposer.bench.multistep`; ``--tasks`` then selects its entries): its records carry
``suite: multistep`` and its report gives per-entry and per-step success and the fully-completed
fraction. ``--dynamics simulator|learned`` changes the pushing MPC's dynamics model (the
simulator itself, or ``voxposer learn-push``'s MLP from ``--push-model``). ``--breakdown RUN …``
runs no new episodes: it attributes every failure of those run folders to perception, dynamics
or specification by counterfactual re-runs (paper Fig. 4; :mod:`voxposer.cli.bench_breakdown`).

Every argument is checked before any work starts (:func:`voxposer.cli.bench_options.check_args`;
a bad one: one line and exit status 2). Ctrl-C, SIGINT (even in a background job that ignores
it) and SIGTERM stop the run the same way: the finished episodes stay in ``episodes.jsonl``
(whole lines), the workers are stopped, the report is written, and the command exits with 128 +
the signal's number and the command line that continues it with ``--resume`` (same code version
only, unless ``--allow-mixed-versions``). A worker process that dies is recorded as a crashed
episode and replaced; after ``kill -9`` of the whole run, ``--resume`` reruns only the episodes
that were running.
"""

from __future__ import annotations

import argparse
import logging
import shlex
import signal
import time
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.markup import escape
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from voxposer.bench.attributes import SPLITS
from voxposer.bench.methods import REFERENCE_BLIND
from voxposer.bench.outputs import write_outputs
from voxposer.bench.results import load_records
from voxposer.bench.runner import run_bench
from voxposer.cli.bench_options import add_bench_options, check_args

# under their former names here too (the tests read them from this module)
from voxposer.cli.bench_options import bench_config as _config
from voxposer.cli.bench_options import default_out as _default_out
from voxposer.cli.interrupts import Interrupted, stop_signals

log = logging.getLogger(__name__)
console = Console(stderr=True)


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register ``bench`` on an argparse sub-parsers object (its options:
    :func:`~voxposer.cli.bench_options.add_bench_options`)."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "bench", help="run the 13-task simulated benchmark (paper Table 4) and write a report")
    add_bench_options(p)
    p.set_defaults(func=run, check=check_args)
    return p


def run(args: argparse.Namespace) -> int:
    """Run the benchmark; exit status 0 when it completed (whatever the success rates)."""
    if getattr(args, "breakdown", None):
        from voxposer.cli.bench_breakdown import run_breakdown

        return run_breakdown(args)
    cfg = _config(args)
    out = args.out or Path("runs") / "bench" / _default_out(cfg)
    results = out / "episodes.jsonl"
    if cfg.llm == "reference":
        console.print("[bold yellow]reference programs[/]: hand-written programs replace the LLM "
                      "(measures perception, planning, control and checks only)")
    if cfg.llm == REFERENCE_BLIND:
        console.print("[bold yellow]constraint-blind control[/]: reference programs minus the "
                      "constraint's map (no LLM); a task tests its constraint only if this fails")
        if cfg.skipped_tasks:
            console.print(f"skipped (no constraint, so no blind control): "
                          f"{', '.join(cfg.skipped_tasks)}")
    console.print(f"seeds: {cfg.seed_set} {cfg.seed_list().start}-{cfg.seed_list().stop - 1}; "
                  f"instructions: {cfg.instructions}; disturbances: "
                  f"{'on' if cfg.disturb else 'off'}; videos: {cfg.video}")
    progress = Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                        MofNCompleteColumn(), TextColumn("{task.fields[rate]}"),
                        TimeElapsedColumn(), TimeRemainingColumn(), console=console)
    bar = progress.add_task(f"{cfg.method}/{cfg.llm}", total=None, rate="")
    counts = {"ok": 0, "n": 0, "errors": 0}
    started = time.perf_counter()

    def on_start(todo: int, done: int) -> None:
        progress.update(bar, total=todo)
        if done:
            console.print(f"resuming: {done} episodes already in {results}")

    def on_record(r: dict[str, Any]) -> None:
        counts["n"] += 1
        counts["ok"] += bool(r["success"])
        counts["errors"] += r.get("error") is not None
        progress.update(bar, advance=1, description=f"{r['task']} ({r['split']})",
                        rate=f"{counts['ok']}/{counts['n']} ok, {counts['errors']} crashed")

    stopped: Interrupted | None = None
    records: list[dict[str, Any]] = []
    with progress, stop_signals():
        try:
            records = run_bench(cfg, results, resume=args.resume, on_record=on_record,
                                on_start=on_start,
                                allow_mixed_versions=args.allow_mixed_versions)
        except KeyboardInterrupt as exc:
            stopped = exc if isinstance(exc, Interrupted) else Interrupted(signal.SIGINT)
    if stopped is not None:
        records = load_records(results)
        console.print(f"[bold red]stopped by {stopped.signal_name}[/]: {counts['n']} new "
                      f"episodes kept in {escape(str(results))} ({len(records)} in all); the "
                      "episodes that were running are not recorded", soft_wrap=True)
    hours = (time.perf_counter() - started) / 3600
    rates = {f"{cfg.method}/{cfg.llm}": counts["n"] / hours} if counts["n"] and hours > 0 else {}
    report = write_outputs(records, out, plot=not args.no_plot, wall_rates=rates,
                           allow_mixed=args.allow_mixed_versions)
    console.print(report.read_text(encoding="utf-8").split("## Task categories")[0], markup=False,
                  highlight=False)
    console.print(f"wrote [bold]{report}[/], [bold]{results}[/]"
                  + ("" if args.no_plot else f", [bold]{out / 'success.png'}[/]"))
    if stopped is not None:
        console.print(f"[bold red]stopped by {stopped.signal_name}[/]; continue with: "
                      f"{escape(resume_command(args, out))}", highlight=False, soft_wrap=True)
        return stopped.exit_status
    return 0


def resume_command(args: argparse.Namespace, out: Path) -> str:
    """The command line that continues this run: its own arguments plus ``--resume`` (and
    ``--out``, when the folder was the default)."""
    argv = list(getattr(args, "argv", None) or ["bench"])
    if "--out" not in argv and not any(a.startswith("--out=") for a in argv):
        argv += ["--out", str(out)]
    if "--resume" not in argv:
        argv.append("--resume")
    return shlex.join(["voxposer", *argv])


__all__ = ["SPLITS", "add_parser", "run"]
