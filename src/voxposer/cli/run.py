"""``voxposer run "<instruction>"``: the main job, in simulation, with live progress.

Builds the seeded MuJoCo tabletop, runs planner → composer → value-map LMPs → closed-loop
``execute`` with the configured language model (default: the bundled local model), shows the
current sub-task, LLM calls, replanning rate and distance to the target
(:mod:`voxposer.cli.run_progress`), and writes to the output folder: ``rollout.mp4`` (one
camera), ``subtask_NN.html`` (composed maps and planned path per sub-task),
``transcript.jsonl`` (prompts, responses, code, errors) and ``summary.json`` (with the
``scene`` it set up: which blocks, lines and open drawers, where, and why). The scene suits
the instruction (:mod:`voxposer.cli.run_scene`); ``--drawer-open`` and ``--place`` override it.
Exit status 0 only when every sub-task reached its target and every post-condition the plan
stated held (``intent`` in ``summary.json``, :mod:`voxposer.lmp.intent`); 2 for a bad argument (checked before
anything runs: :func:`check_args`).
``--frames DIR --robot none`` plans on recorded frames instead, moving no robot
(:mod:`voxposer.cli.run_frames`).
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import re
import resource
import time
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from rich.console import Console
from rich.live import Live

from voxposer import tabletop
from voxposer.cli.checks import (
    check_llm_options,
    check_out_dir,
    check_seconds,
    check_seed,
    check_text,
)
from voxposer.cli.llm_options import add_llm_options
from voxposer.cli.perception_options import (
    OPEN_VOCAB,
    add_open_vocab_options,
    check_open_vocab_options,
    open_vocab_from_args,
)
from voxposer.cli.run_frames import add_frame_options, check_frame_options, rollout_frames
from voxposer.cli.run_progress import RunProgress, progress_backend
from voxposer.cli.run_scene import CLOSE_OPENING_M, SceneRequest, allowed_range, choose_scene
from voxposer.errors import ConfigError, VoxPoserError

#: ``--perception`` values (:data:`voxposer.pipeline.PERCEPTIONS`; kept here so the CLI's help
#: needs no simulator import).
PERCEPTION_CHOICES = ("ground-truth", "colour-depth", "ground-truth-noisy", "colour-depth-noisy",
                      "colour-depth-tracked", "colour-depth-tracked-noisy", OPEN_VOCAB)

if TYPE_CHECKING:
    from voxposer.envs.layout import SceneLayout

log = logging.getLogger(__name__)
console = Console(stderr=True)


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register ``run`` on an argparse sub-parsers object."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "run", help="carry out an instruction in the simulated tabletop (LLM → value maps → robot)"
    )
    p.add_argument("instruction", help='e.g. "push the blue block to the back left corner"')
    p.add_argument("--seed", type=int, default=0, help="scene seed")
    p.add_argument(
        "--out", type=Path, default=None, help="output folder (default runs/<time>-<words>)"
    )
    add_llm_options(p)
    p.add_argument(
        "--disturb",
        action="store_true",
        help="apply the paper's disturbances during the rollout: robot push, object "
        "displacement, reverting progress, at 20/40/60%% of a sub-task's progress",
    )
    p.add_argument("--max-time", type=float, default=40.0, help="simulated seconds per sub-task")
    p.add_argument("--no-video", action="store_true", help="skip the MP4")
    p.add_argument("--camera-hz", type=float, default=None, metavar="HZ",
                   help="each camera streams at this rate in simulated time and an observation "
                   "holds the latest frame of each (at 2.5 Hz, two of the four views are new at "
                   "each 5 Hz replan); default: every camera renders at every observation")
    p.add_argument("--perception", choices=PERCEPTION_CHOICES, default=None,
                   help="how objects are found: the simulator's segmentation (ground-truth, "
                   "default) or RGB-D pixels only (colour-depth, default with --frames); -noisy: "
                   "on views with a consumer RGB-D camera's errors (depth noise, missing depth, "
                   "calibration; masks too); -tracked: pixel labels carried between "
                   "detections; open-vocab: OWLv2 + SAM from --detector/--segmenter")
    add_open_vocab_options(p)
    _add_scene_options(p)
    add_frame_options(p)
    p.set_defaults(func=run, check=check_args)
    return p


def check_args(args: argparse.Namespace) -> None:
    """Refuse bad arguments before the world or a model is built.

    Raises:
        ConfigError: an empty instruction, a negative ``--seed``, a ``--max-time`` that is not a
            positive number of seconds, an ``--out`` that is a file, a bad ``--place`` /
            ``--drawer-open``, a ``--camera-hz`` that is not a positive rate, or language-model
            options the backend cannot use.
    """
    check_text(args.instruction, "instruction", "push the blue block to the back left corner")
    check_seed(args.seed)
    check_seconds(args.max_time)
    if args.camera_hz is not None and not (math.isfinite(args.camera_hz) and args.camera_hz > 0):
        raise ConfigError(f"--camera-hz must be a frame rate > 0 [Hz], got {args.camera_hz!r}")
    check_out_dir(args.out)
    SceneRequest.from_options(args.drawer_open, args.place)
    check_llm_options(args, args.llm)
    check_frame_options(args)  # --frames / --robot; sets --perception's default
    check_open_vocab_options(args)


def _add_scene_options(parser: argparse.ArgumentParser) -> None:
    """The ``scene`` option group of ``voxposer run``."""
    group = parser.add_argument_group("scene")
    group.add_argument(
        "--drawer-open", action="append", default=[], metavar="top|middle|bottom[=M]",
        help=f"start with this drawer open (repeatable; default {CLOSE_OPENING_M} m, at most "
        f"{tabletop.DRAWER_TRAVEL} m); replaces the drawer the instruction implies")
    (xlo, xhi), (ylo, yhi) = allowed_range("block")
    group.add_argument(
        "--place", action="append", default=[], metavar='"<colour> block=<x>,<y>"',
        help="put a block (or line) at (x, y) on the table [m] (repeatable; front +x, left -y; "
        f"a block's x in [{xlo:.3f}, {xhi:.3f}], y in [{ylo:.3f}, {yhi:.3f}])")


def _out_dir(args: argparse.Namespace) -> Path:
    if args.out is not None:
        return Path(args.out)
    words = "-".join(re.findall(r"[a-z0-9]+", args.instruction.lower())[:6]) or "run"
    return Path("runs") / f"{time.strftime('%Y%m%d-%H%M%S')}-{words}"


def _backend(args: argparse.Namespace) -> Any:
    from voxposer.cli.llm_options import backend_from_args

    return backend_from_args(args)


def scene_layout(instruction: str, rng: np.random.Generator | None = None,
                 request: SceneRequest | None = None) -> SceneLayout:
    """The scene for an instruction (:func:`voxposer.cli.run_scene.choose_scene`): every block
    and line it names, plus distractors; a drawer it asks to close starts open
    (``CLOSE_OPENING_M``), one it asks to open starts closed; ``request`` overrides."""
    return choose_scene(instruction, rng or np.random.default_rng(0), request).layout


def run(args: argparse.Namespace) -> int:
    """Carry out ``args.instruction``; returns the exit status (0 only on success).

    Raises:
        ConfigError: a bad ``--place`` / ``--drawer-open`` value, before anything runs (the CLI
            calls :func:`check_args` first).
    """
    request = SceneRequest.from_options(args.drawer_open, args.place)
    out = _out_dir(args)
    out.mkdir(parents=True, exist_ok=True)
    summary: dict[str, Any] = {
        "instruction": args.instruction,
        "seed": args.seed,
        "perception": args.perception,
        "success": False,
        "reason": "",
        "message": "",
        "scene": None,
        "subtasks": [],
        "llm_calls": 0,
        "disturbances": [],
    }
    started = time.perf_counter()
    try:
        _rollout(args, request, out, summary)
    except VoxPoserError as err:  # setup failures (model, recordings, scene) end here too
        summary.update(success=False, reason=type(err).__name__, message=str(err))
    summary["timings_s"] = {
        "total": round(time.perf_counter() - started, 2),
        **summary.get("timings_s", {}),
    }
    # peak resident memory of this process [MiB] (ru_maxrss is in KiB on Linux)
    summary["peak_rss_mb"] = round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
    summary["outputs"] = sorted(p.name for p in out.iterdir() if p.name != "summary.json")
    (out / "summary.json").write_text(json.dumps(summary, indent=2))
    style = "bold green" if summary["success"] else "bold red"
    console.print(
        f"[{style}]{'success' if summary['success'] else 'failure'}[/]: {summary['message']}"
    )
    console.print(f"outputs in [bold]{out}[/bold] (peak memory {summary['peak_rss_mb']} MiB)")
    return 0 if summary["success"] else 1


def _subtask_summary(record: Any) -> dict[str, Any]:
    """One executed sub-task as ``summary.json`` lists it."""
    r = record.result
    return {
        "subtask": record.subtask,
        "success": r.success,
        "reason": r.reason,
        "message": r.message,
        "replans": r.replans,
        "replan_hz": round(r.replan_hz, 2),
        "sim_time_s": round(r.sim_time, 2),
        "final_distance_m": round(r.final_distance, 4),
        "picture": record.picture.name if record.picture else None,
    }


def _rollout(args: argparse.Namespace, request: SceneRequest, out: Path,
             summary: dict[str, Any]) -> None:
    """Build the world and the LMPs, run the instruction, fill ``summary`` as it goes."""
    if args.frames is not None:  # recorded frames, no robot: plan only (cli/run_frames.py)
        return rollout_frames(args, _backend(args), out, summary)
    from voxposer.control import ExecutorConfig
    from voxposer.control.disturbance_schedule import DisturbanceSchedule, Disturber
    from voxposer.control.recording import VideoRecorder
    from voxposer.envs import TabletopWorld, WorldConfig
    from voxposer.lmp.transcript import Transcript
    from voxposer.pipeline import Embodiment, voxposer_runtime

    progress = RunProgress(args.instruction)
    rng = np.random.default_rng(args.seed)
    config = WorldConfig()
    world = TabletopWorld(replace(config, cameras=replace(config.cameras,
                                                          frame_hz=args.camera_hz)))
    scene = choose_scene(args.instruction, rng, request)
    layout = scene.layout
    summary["scene"] = scene.describe()  # what was asked, should the reset fail
    summary["scene"] = scene.describe(world.reset(rng, layout))
    backend = progress_backend(_backend(args), progress)
    summary["model"] = backend.model
    summary["camera_hz"] = args.camera_hz
    transcript = Transcript(out / "transcript.jsonl")
    runtime, executor = voxposer_runtime(
        Embodiment(world, open_vocab_from_args(world, world.grid, args))
        if args.perception == OPEN_VOCAB else Embodiment.simulated(world, args.perception),
        backend, rng,
        executor_config=ExecutorConfig(max_time_s=args.max_time), picture_dir=out,
        transcript=transcript)
    disturber = None
    if args.disturb:  # on sub-task progress (voxposer.control.disturbance_schedule)
        relevant = tuple(f"{c} block" for c in layout.blocks)
        disturber = Disturber(world, rng.spawn(1)[0], relevant,
                              schedule=DisturbanceSchedule(
                                  reach_tolerance_m=executor.config.reach_tolerance_m))

    def on_replan(result: Any, plan: Any) -> None:
        progress.replans += 1
        progress.hz = result.replan_hz
        progress.distance = result.final_distance
        if disturber is not None:
            disturber.on_replan(result, plan)

    def on_subtask(subtask: str) -> None:
        progress.subtask = subtask

    executor.on_replan = on_replan
    executor.on_subtask = on_subtask
    recorder = None if args.no_video else VideoRecorder(world, out / "rollout.mp4")
    try:
        with Live(progress, console=console, refresh_per_second=4, transient=False):
            runtime.run(args.instruction)
        console.print()
        done = bool(executor.records)
        summary.update(
            success=done,
            reason="reached" if done else "nothing_executed",
            message="every sub-task reached its target"
            if done
            else "the programs never called execute()",
        )
        failed = runtime.intent.failed()
        if done and failed:  # success needs the targets reached and the post-conditions true
            first = failed[0]
            summary.update(success=False, reason="post_condition_failed",
                           message=f"after {first.subtask!r}, the post-condition "
                                   f"{first.condition} did not hold ({first.measured})")
    finally:
        summary["intent"] = [r.to_json() for r in runtime.intent.results]
        if recorder is not None:
            recorder.close()
        backend.close()
        summary["subtasks"] = [_subtask_summary(r) for r in executor.records]
        summary["llm_calls"] = runtime.llm_calls
        summary["timings_s"] = {
            "llm": round(
                sum(e.get("seconds", 0.0) for e in transcript.events if e["event"] == "llm_call"), 2
            )
        }
        summary["disturbances"] = disturber.applied if disturber else []
