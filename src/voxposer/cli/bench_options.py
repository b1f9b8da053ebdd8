"""``voxposer bench``'s options: their definitions, their checks, and the BenchConfig they make.

:func:`add_bench_options` declares every option of the command (:mod:`voxposer.cli.bench`
registers it and runs it); :func:`check_args` refuses a bad value before any work starts;
:func:`bench_config` turns the parsed options into a
:class:`~voxposer.bench.run_config.BenchConfig`, and :func:`default_out` names its default output
folder.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import Any

from voxposer.bench.attributes import SPLITS
from voxposer.bench.methods import BACKENDLESS_LLMS, METHODS, NO_LLM, REFERENCE_LLMS, UNET_MP
from voxposer.bench.multistep import ENTRIES
from voxposer.bench.protocol import INSTRUCTION_SPLITS, SEED_SETS
from voxposer.bench.run_config import BenchConfig
from voxposer.bench.suites import MULTISTEP_SUITE, SUITES, TASKS_SUITE, check_suite, suite_names
from voxposer.bench.tasks import TASKS
from voxposer.cli.checks import (
    check_int,
    check_llm_options,
    check_out_dir,
    check_seconds,
    check_seed,
)
from voxposer.cli.llm_options import add_llm_options, llm_overrides
from voxposer.errors import ConfigError
from voxposer.pipeline import PERCEPTIONS


def add_bench_options(p: argparse.ArgumentParser) -> None:
    """Declare every option of ``voxposer bench`` on its parser ``p``."""
    p.add_argument("--suite", default=TASKS_SUITE,
                   help=f"instruction suite, one of: {', '.join(SUITES)} ({TASKS_SUITE}: the 13 "
                   f"tasks; {MULTISTEP_SUITE}: 2-3 step instructions, a check per step and "
                   "for their order)")
    p.add_argument("--tasks", default="all",
                   help=f"comma-separated task names of the suite or 'all' (tasks: "
                   f"{', '.join(TASKS)}; {MULTISTEP_SUITE} entries: {', '.join(ENTRIES)})")
    p.add_argument("--splits", default="seen,unseen",
                   help="attribute splits: seen, unseen, both, or a comma-separated list "
                   "(default: both)")
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
                   "seeds; vague-relational: those with objects named by relation and quantities "
                   "said vaguely; LLMs only)")
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
                   "-tracked: the pixel labels carried between detections; recorded in every "
                   "episode")
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
    cfg = bench_config(args)
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


def bench_config(args: argparse.Namespace) -> BenchConfig:
    """The run the parsed options ask for.

    Raises:
        ConfigError: an empty or repeated ``--tasks`` / ``--splits`` name, and every check of
            :class:`BenchConfig`.
    """
    suite = check_suite(getattr(args, "suite", TASKS_SUITE))
    known = suite_names(suite)
    tasks = known if args.tasks.strip() == "all" else _names(args.tasks, "--tasks", known)
    overrides = llm_overrides(args)
    kwargs: dict[str, Any] = {}
    if args.workers is not None:
        kwargs["workers"] = args.workers
    splits = SPLITS if args.splits.strip() == "both" else _names(args.splits, "--splits", SPLITS)
    return BenchConfig(tasks=tasks, splits=splits,
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


def default_out(cfg: BenchConfig) -> str:
    """The default output folder's name (under ``runs/bench/``): ``<method>-<llm>`` plus the
    non-default suite, perception, dynamics, seed set and instruction split."""
    name = f"{cfg.method}-{cfg.llm}" + ("" if cfg.suite == TASKS_SUITE else f"-{cfg.suite}")
    if cfg.perception != "ground-truth":
        name += f"-{cfg.perception}"
    if cfg.dynamics != "heuristic":
        name += f"-{cfg.dynamics}-dynamics"
    if cfg.seed_set != "dev":
        name += f"-{cfg.seed_set}"
    return name + ("" if cfg.instructions == "seen" else f"-{cfg.instructions}-instructions")


__all__ = ["add_bench_options", "bench_config", "check_args", "default_out",
           "max_local_workers"]
