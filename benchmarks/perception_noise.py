"""Pixel perception with and without sensor errors: the colour-depth detector on noisy views.

On benchmark scenes (``reset_episode`` of each task in turn, dev seeds 0, 1, …, the arm at
home), every object the clean ground-truth :class:`~voxposer.perception.SegmentationPerceiver`
sees is detected by :class:`~voxposer.perception.colour_depth.ColourDepthPerceiver` on the
clean views, on views with each effect of :class:`~voxposer.perception.SensorNoiseConfig` alone
(typical RealSense D435 defaults), and with all of them ("colour-depth-noisy"); and by the
ground-truth perceiver on noisy views with corrupted masks ("ground-truth-noisy"). With
calibration error the cameras are registered against each other, as the pipeline does
(:mod:`voxposer.perception.view_registration`); the "_unregistered" conditions show what that
removes. Per condition: detection rate (of the objects clean ground truth sees) and the 3-D
centre error against clean ground truth [cm] (median, 95th percentile; centre = the box centre
both report), its maximum and the kind it occurred on, and the median error of a block's
horizontal box sides [cm]; then the median centre error per object kind. Noise is seeded
from each scene, as in :func:`voxposer.pipeline.simulated_perceiver`. The last line is
machine-readable.

    MUJOCO_GL=egl python benchmarks/perception_noise.py [--scenes 20] [--tasks a,b]
"""

from __future__ import annotations

import argparse
import os
import time
from collections import defaultdict
from typing import Any

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np
from rich.console import Console
from rich.table import Table

from voxposer import catalog
from voxposer.bench.task import reset_episode
from voxposer.bench.tasks import TASKS
from voxposer.envs import TabletopWorld
from voxposer.errors import VoxPoserError
from voxposer.perception import SegmentationPerceiver, SensorNoiseConfig
from voxposer.perception.perceiver import Perceiver
from voxposer.pipeline import simulated_perceiver

KINDS = ("block", "line", "cabinet", "drawer", "handle", "table", "robot", "gripper")


def conditions() -> dict[str, tuple[str, SensorNoiseConfig | None, bool]]:
    """Condition name → (perception mode, noise config (None: the mode's default), whether
    the cameras are registered against each other, as the pipeline does)."""
    typical = SensorNoiseConfig()
    out: dict[str, tuple[str, SensorNoiseConfig | None, bool]] = {
        "clean": ("colour-depth", None, True)}
    for effect in ("depth_noise", "edge_dropout", "dark_dropout", "calibration"):
        out[f"only_{effect}"] = ("colour-depth-noisy", typical.only(effect), True)
    out["only_calibration_unregistered"] = ("colour-depth-noisy", typical.only("calibration"),
                                            False)
    out["noisy"] = ("colour-depth-noisy", typical, True)
    out["noisy_unregistered"] = ("colour-depth-noisy", typical, False)
    out["gt_noisy"] = ("ground-truth-noisy", typical, True)
    return out


Stats = dict[str, dict[str, list[float]]]


def score_scene(world: Any, stats: dict[str, Stats]) -> None:
    """Detect every object clean ground truth sees under each condition; append to ``stats``
    (condition → kind → "found" (0/1), "err_cm" and "size_cm" values; size: the largest
    difference of the box's horizontal sides from clean ground truth's, as the cameras' smear
    widens an object)."""
    truth = SegmentationPerceiver(world, world.grid)
    visible = {}
    for name in world.object_names:
        try:
            visible[name] = truth.detect(name)
        except VoxPoserError:
            continue  # ground truth does not see it either
    for cond, (mode, noise, register) in conditions().items():
        perceiver: Perceiver = simulated_perceiver(world, mode, noise=noise, register=register)
        for name, gt in visible.items():
            kind = catalog.object_named(name).kind
            try:
                got = perceiver.detect(name)
            except VoxPoserError:
                stats[cond][kind]["found"].append(0.0)
                continue
            stats[cond][kind]["found"].append(1.0)
            stats[cond][kind]["err_cm"].append(float(np.linalg.norm(got.position - gt.position))
                                               * 100)
            sides = lambda box: np.asarray(box[1] - box[0])[:2]  # noqa: E731
            stats[cond][kind]["size_cm"].append(
                float(np.max(np.abs(sides(got.aabb) - sides(gt.aabb)))) * 100)


def summarise(stats: dict[str, Stats]) -> tuple[Table, Table, dict[str, float]]:
    """The per-condition table, the per-kind table and the machine-readable figures."""
    overall = Table(title="colour-depth centre error vs clean ground truth, by sensor condition")
    for col in ("condition", "objects", "detected", "err med (cm)", "err p95 (cm)",
                "err max (cm)", "worst", "block size med (cm)"):
        overall.add_column(col, justify="right")
    by_kind = Table(title="median centre error (cm) per kind")
    by_kind.add_column("condition", justify="right")
    for kind in KINDS:
        by_kind.add_column(kind, justify="right")
    line: dict[str, float] = {}
    for cond, kinds in stats.items():
        found = [v for s in kinds.values() for v in s["found"]]
        err = np.asarray([v for s in kinds.values() for v in s["err_cm"]])
        det = float(np.mean(found)) if found else float("nan")
        med = float(np.median(err)) if len(err) else float("nan")
        p95 = float(np.percentile(err, 95)) if len(err) else float("nan")
        worst = max(((max(s["err_cm"]), k) for k, s in kinds.items() if s["err_cm"]),
                    default=(float("nan"), ""))
        size = float(np.median(kinds["block"]["size_cm"])) if kinds["block"]["size_cm"] \
            else float("nan")
        overall.add_row(cond, str(len(found)), f"{det:.3f}", f"{med:.2f}", f"{p95:.2f}",
                        f"{worst[0]:.2f}", worst[1], f"{size:.2f}")
        by_kind.add_row(cond, *(f"{np.median(kinds[k]['err_cm']):.2f}" if kinds[k]["err_cm"]
                                else "" for k in KINDS))
        line.update({f"{cond}_det": round(det, 3), f"{cond}_err_med_cm": round(med, 2),
                     f"{cond}_err_p95_cm": round(p95, 2), f"{cond}_err_max_cm": round(worst[0], 2),
                     f"{cond}_block_size_med_cm": round(size, 2)})
    return overall, by_kind, line


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=20, help="scenes (tasks taken in turn)")
    parser.add_argument("--tasks", default="all", help="comma-separated task names or 'all'")
    parser.add_argument("--split", default="seen", help="attribute split of the scenes")
    args = parser.parse_args()
    console = Console(stderr=True, width=120)
    tasks = list(TASKS) if args.tasks == "all" else args.tasks.split(",")
    world = TabletopWorld()
    stats: dict[str, Stats] = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    start = time.perf_counter()
    for k in range(args.scenes):
        reset_episode(TASKS[tasks[k % len(tasks)]], world, args.split, k // len(tasks))
        score_scene(world, stats)
    elapsed = time.perf_counter() - start
    overall, by_kind, line = summarise(stats)
    console.print(overall)
    console.print(by_kind)
    line.update(scenes=args.scenes, seconds=round(elapsed, 1))
    print(" ".join(f"{k}={v}" for k, v in line.items()))


if __name__ == "__main__":
    main()
