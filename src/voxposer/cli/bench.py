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

Every argument is checked before any work starts (:func:`check_args`; a bad one: one line and
exit status 2). Ctrl-C, SIGINT (even in a background job that ignores it) and SIGTERM stop the
run the same way: the finished episodes stay in ``episodes.jsonl`` (whole lines), the workers
are stopped, the report is written, and the command exits with 128 + the signal's number and
the command line that continues it with ``--resume`` (same code version only, unless
``--allow-mixed-versions``). A worker process that dies is recorded as a crashed episode and
replaced; after ``kill -9`` of the whole run, ``--resume`` reruns only the episodes that were
running.
"""

from __future__ import annotations

import argparse
import logging
import os
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
from voxposer.bench.methods import (
    BACKENDLESS_LLMS,
    METHODS,
    NO_LLM,
    REFERENCE_BLIND,
    REFERENCE_LLMS,
    UNET_MP,
)
from voxposer.bench.multistep import ENTRIES
from voxposer.bench.outputs import write_outputs
from voxposer.bench.protocol import INSTRUCTION_SPLITS, SEED_SETS
from voxposer.bench.results import load_records
from voxposer.bench.runner import BenchConfig, run_bench
from voxposer.bench.suites import MULTISTEP_SUITE, SUITES, TASKS_SUITE, check_suite, suite_names
from voxposer.bench.tasks import TASKS
from voxposer.cli.checks import (
    check_int,
    check_llm_options,
    check_out_dir,
    check_seconds,
    check_seed,
)
from voxposer.cli.interrupts import Interrupted, stop_signals
from voxposer.cli.llm_options import add_llm_options, llm_overrides
from voxposer.errors import ConfigError
from voxposer.pipeline import PERCEPTIONS

log = logging.getLogger(__name__)
console = Console(stderr=True)


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register ``bench`` on an argparse sub-parsers object."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "bench", help="run the 13-task simulated benchmark (paper Table 4) and write a report")
    p.add_argument("--suite", default=TASKS_SUITE,
                   help=f"instruction suite, one of: {', '.join(SUITES)} ({TASKS_SUITE}: the 13 "
                   f"tasks; {MULTISTEP_SUITE}: 2-3 step instructions, a check per step and "
                   "for their order)")
    p.add_argument("--tasks", default="all",
                   help=f"comma-separated task names of the suite or 'all' (tasks: "
                   f"{', '.join(TASKS)}; {MULTISTEP_SUITE} entries: {', '.join(ENTRIES)})")
    p.add_argument("--splits", default="seen,unseen", help="seen, unseen or both")
    p.add_argument("--episodes", type=int, default=20, help="episodes per task and split")
    p.add_argument("--seeds", default=None,
                   help="seed set: " + ", ".join(f"{s.name} ({s.first}-{s.last})"
                                                 for s in SEED_SETS.values())
                   + "; runs its first --episodes seeds (default: dev, unless --seed)")
    p.add_argument("--seed", type=int, default=None,
                   help="ad-hoc run: first episode seed (instead of --seeds)")
    p.add_argument("--instructions", default="seen",
                   help=f"instruction split, one of: {', '.join(INSTRUCTION_SPLITS)} (unseen: "
                   "each task's few-shot examples are held out of every prompt; paraphrased: "
                   "reworded instructions, dev phrasings on dev seeds and test phrasings on test "
                   "seeds; LLMs only)")
    p.add_argument("--method", default="voxposer", help=f"one of: {', '.join(METHODS)}")
    p.add_argument("--unet-checkpoint", type=Path, default=None,
                   help=f"the U-Net of --method {UNET_MP} (model.pt of voxposer train-unet; "
                   "required there, refused with other methods)")
    add_llm_options(p, extra_choices=REFERENCE_LLMS, default=None, record=False,
                    extra_help="; 'reference' = hand-written reference programs (no LLM); "
                    "'reference-blind' = the same minus the constraint's map (control); "
                    f"none with --method {UNET_MP}")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default: cores)")
    p.add_argument("--pool", choices=("local", "ray"), default="local",
                   help="local process pool, or a Ray cluster (pip install 'voxposer[ray]')")
    p.add_argument("--ray-address", default=None, help="Ray cluster address (--pool ray)")
    p.add_argument("--max-time", type=float, default=40.0, help="simulated seconds per sub-task")
    p.add_argument("--out", type=Path, default=None,
                   help="output folder (default runs/bench/<method>-<llm>)")
    p.add_argument("--resume", action="store_true", help="continue the episodes.jsonl in --out")
    p.add_argument("--allow-mixed-versions", action="store_true",
                   help="resume, and report, records of different code versions together")
    p.add_argument("--fresh-cache", action="store_true",
                   help="answer from a response cache of this run only (<out>/cache/, empty at "
                   "the start); the prefix-state cache stays shared")
    p.add_argument("--video", default="none",
                   help="record an MP4 per episode into <out>/videos/: none, failures (kept for "
                   "failed episodes only) or all")
    p.add_argument("--disturb", action="store_true",
                   help="apply the paper's disturbances (robot push, object displacement, "
                   "reverting progress) on a schedule of each sub-task's progress; records are "
                   "marked disturbed, so --resume can add them beside static ones")
    p.add_argument("--perception", choices=PERCEPTIONS, default="ground-truth",
                   help="how objects are found: the simulator's segmentation (ground-truth) or "
                   "RGB-D pixels only (colour-depth); -noisy: on views with a consumer RGB-D "
                   "camera's errors (depth noise, missing depth, calibration; masks too); "
                   "recorded in every episode")
    p.add_argument("--dynamics", default="heuristic",
                   help="the pushing MPC's dynamics model: heuristic (the paper's: the object "
                   "translates with the push), simulator (each sampled push simulated; slow) or "
                   "learned (an MLP from voxposer learn-push, with --push-model)")
    p.add_argument("--push-model", type=Path, default=None,
                   help="push_model.npz of voxposer learn-push (--dynamics learned)")
    p.add_argument("--breakdown", type=Path, nargs="+", default=None, metavar="RUN",
                   help="instead of running episodes: attribute every failed episode of these "
                   "run folders to perception, dynamics or specification by counterfactual "
                   "re-runs (paper Fig. 4); writes <run>/breakdown.jsonl and, into --out "
                   "(default runs/breakdown), breakdown.md and breakdown.png")
    p.add_argument("--no-plot", action="store_true", help="skip success.png")
    p.set_defaults(func=run, check=check_args)
    return p


def max_local_workers() -> int:
    """The most ``--workers`` of the local pool: 4 per core (at least 8)."""
    return max(8, 4 * (os.cpu_count() or 1))


def check_args(args: argparse.Namespace) -> None:
    """Refuse bad arguments before any world, model or worker is started.

    Raises:
        ConfigError: names the option, its value and what is allowed (``--episodes 0``,
            ``--workers 0``, ``--seed -5``, ``--max-time 0``, an empty ``--tasks``…), and every
            check of :class:`BenchConfig` and of the LLM options.
    """
    if getattr(args, "breakdown", None):
        from voxposer.cli.bench_breakdown import check_breakdown

        check_out_dir(args.out)
        check_breakdown(args)
        return
    check_int(args.episodes, "--episodes", 1)
    check_seed(args.seed)
    if args.workers is not None:
        check_int(args.workers, "--workers", 1,
                  max_local_workers() if args.pool == "local" else None)
    check_seconds(args.max_time)
    check_out_dir(args.out)
    if args.ray_address is not None and args.pool != "ray":
        raise ConfigError(f"--ray-address {args.ray_address!r} is for --pool ray; got --pool "
                          f"{args.pool}")
    cfg = _config(args)
    if cfg.llm not in BACKENDLESS_LLMS:
        check_llm_options(args, cfg.llm)


def _names(value: str, option: str, known: tuple[str, ...]) -> tuple[str, ...]:
    """The comma-separated names of ``option`` (unknown ones are left to BenchConfig)."""
    names = tuple(n.strip() for n in value.split(",") if n.strip())
    if not names:
        raise ConfigError(f"{option} names nothing ({value!r}); give one or more of: "
                          f"{', '.join(known)}")
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ConfigError(f"{option} names {', '.join(map(repr, twice))} more than once "
                          f"({value!r}); give each once")
    return names


def _config(args: argparse.Namespace) -> BenchConfig:
    suite = check_suite(getattr(args, "suite", TASKS_SUITE))
    known = suite_names(suite)
    tasks = known if args.tasks.strip() == "all" else _names(args.tasks, "--tasks", known)
    overrides = llm_overrides(args)
    kwargs: dict[str, Any] = {}
    if args.workers is not None:
        kwargs["workers"] = args.workers
    return BenchConfig(tasks=tasks, splits=_names(args.splits, "--splits", SPLITS),
                       episodes=args.episodes, seeds=args.seeds, seed=args.seed,
                       method=args.method, instructions=args.instructions,
                       llm=args.llm or (NO_LLM if args.method == UNET_MP else "default"),
                       unet_checkpoint=getattr(args, "unet_checkpoint", None),
                       pool=args.pool, ray_address=args.ray_address,
                       max_time_s=args.max_time, llm_overrides=overrides,
                       fresh_cache=args.fresh_cache, video=args.video, disturb=args.disturb,
                       suite=suite, perception=args.perception,
                       dynamics=getattr(args, "dynamics", "heuristic"),
                       push_model=getattr(args, "push_model", None), **kwargs)


def _default_out(cfg: BenchConfig) -> str:
    """``<method>-<llm>`` plus the non-default seed set and instruction split."""
    name = f"{cfg.method}-{cfg.llm}" + ("" if cfg.suite == TASKS_SUITE else f"-{cfg.suite}")
    if cfg.perception != "ground-truth":
        name += f"-{cfg.perception}"
    if cfg.dynamics != "heuristic":
        name += f"-{cfg.dynamics}-dynamics"
    if cfg.seed_set != "dev":
        name += f"-{cfg.seed_set}"
    return name + ("" if cfg.instructions == "seen" else f"-{cfg.instructions}-instructions")


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
