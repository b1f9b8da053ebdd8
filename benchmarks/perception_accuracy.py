"""Pixel perception against ground truth: the colour-depth detector on benchmark scenes.

For every benchmark task and dev seed (``reset_episode``, so the scenes the benchmark runs),
:class:`~voxposer.perception.colour_depth.ColourDepthPerceiver` (RGB + depth only) and the
ground-truth :class:`~voxposer.perception.segmentation.SegmentationPerceiver` detect every
object of the scene. Per object kind: detection rate (of the objects ground truth sees), centre
error [cm] (median, p90; centre = the box centre both report), 3-D box IoU, false detections
(names reported that the scene does not hold), and, for drawers, the measured opening's error
against the joint [cm]. ``label_ms`` is the time of one labelling of the 4 views (median),
``observe_ms`` the extra rendering of colour it needs (``gt_ms``: ground truth's fusion, for
comparison). Each scene is scored twice: as reset (the arm at home), and with the arm reaching
the task's object (the open gripper around a block, or in front of a drawer's handle), where
the gripper hides and touches what it reaches. The last line is machine-readable (the two
states pooled).

    MUJOCO_GL=egl python benchmarks/perception_accuracy.py [--seeds 10] [--tasks a,b]
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
from voxposer.geometry.frames import TOP_DOWN_QUAT
from voxposer.perception import SegmentationPerceiver
from voxposer.perception.colour_depth import ColourDepthPerceiver


def box_iou(a: np.ndarray, b: np.ndarray) -> float:
    """IoU of two axis-aligned boxes, shapes (2, 3) [m] (rows min, max)."""
    lo, hi = np.maximum(a[0], b[0]), np.minimum(a[1], b[1])
    inter = float(np.prod(np.clip(hi - lo, 0.0, None)))
    vol_a, vol_b = (float(np.prod(np.clip(box[1] - box[0], 1e-6, None))) for box in (a, b))
    return inter / (vol_a + vol_b - inter)


def score_scene(world: Any, stats: dict[str, dict[str, list[float]]]) -> None:
    """Detect every object of ``world``'s scene both ways; append per-kind figures to
    ``stats`` (kind → figure → values)."""
    truth = SegmentationPerceiver(world, world.grid)
    pixels = ColourDepthPerceiver(world, world.grid)
    world._obs = None  # time the rendering from scratch (drop the cached observation)
    start = time.perf_counter()
    world.observe(rgb=False)
    depth_only = time.perf_counter() - start
    start = time.perf_counter()
    truth.point_cloud()
    stats["all"]["gt_ms"].append((time.perf_counter() - start) * 1e3)
    world._obs = None
    start = time.perf_counter()
    world.observe(rgb=True)
    stats["all"]["observe_ms"].append((time.perf_counter() - start - depth_only) * 1e3)
    names = pixels.object_names
    stats["all"]["label_ms"].append(pixels.label_times_ms[-1])
    for name in names:
        if name not in world.object_names:
            stats[catalog.object_named(name).kind]["false"].append(1.0)
    for name in world.object_names:
        kind = catalog.object_named(name).kind
        try:
            gt = truth.detect(name)
        except VoxPoserError:
            continue  # ground truth does not see it either
        try:
            got = pixels.detect(name)
        except VoxPoserError:
            stats[kind]["found"].append(0.0)
            continue
        stats[kind]["found"].append(1.0)
        stats[kind]["false"].append(0.0)
        stats[kind]["err_cm"].append(float(np.linalg.norm(got.position - gt.position)) * 100)
        stats[kind]["iou"].append(box_iou(np.asarray(got.aabb), np.asarray(gt.aabb)))
        if kind == "drawer":
            which = name.removesuffix(" drawer")
            stats[kind]["open_err_cm"].append(
                abs(pixels.drawer_opening(which) - world.drawer_opening(which)) * 100)


def reach(world: Any, attrs: dict[str, str]) -> bool:
    """Move the open gripper to the task's first object (around a block, or 5 cm in front of
    a drawer's handle); False when the task names none or the move fails."""
    for value in attrs.values():
        name = value if value in world.object_names else f"{value} drawer handle"
        if name not in world.object_names:
            continue
        target = world.object_position(name) + (
            np.array([0.0, -0.05, 0.0]) if name.endswith("handle") else np.array([0.0, 0.0, 0.01]))
        try:
            return world.move_to_pose(target, TOP_DOWN_QUAT, gripper=0.0).reached
        except VoxPoserError:
            return False
    return False


def summarise(stats: dict[str, dict[str, list[float]]], title: str
              ) -> tuple[Table, dict[str, float]]:
    table = Table(title=title)
    for col in ("kind", "objects", "detected", "false", "err med [cm]", "err p90 [cm]",
                "IoU med", "opening err p90 [cm]"):
        table.add_column(col, justify="right")
    line: dict[str, float] = {}
    for kind in ("block", "line", "cabinet", "drawer", "handle", "table", "robot", "gripper"):
        s = stats.get(kind)
        if not s or not s["found"]:
            continue
        found, err, iou = np.mean(s["found"]), np.asarray(s["err_cm"]), np.asarray(s["iou"])
        false = float(np.sum(s["false"]))
        med = float(np.median(err)) if len(err) else float("nan")
        p90 = float(np.percentile(err, 90)) if len(err) else float("nan")
        miou = float(np.median(iou)) if len(iou) else float("nan")
        opening = (float(np.percentile(s["open_err_cm"], 90)) if s.get("open_err_cm")
                   else float("nan"))
        table.add_row(kind, str(len(s["found"])), f"{found:.3f}", f"{false:.0f}", f"{med:.2f}",
                      f"{p90:.2f}", f"{miou:.3f}", "" if np.isnan(opening) else f"{opening:.2f}")
        line.update({f"{kind}_det": round(float(found), 3), f"{kind}_err_med_cm": round(med, 2),
                     f"{kind}_err_p90_cm": round(p90, 2), f"{kind}_iou": round(miou, 3),
                     f"{kind}_false": false})
        if not np.isnan(opening):
            line["drawer_open_err_p90_cm"] = round(opening, 2)
    line["label_ms"] = round(float(np.median(stats["all"]["label_ms"])), 1)
    line["gt_ms"] = round(float(np.median(stats["all"]["gt_ms"])), 1)
    line["observe_ms"] = round(float(np.median(stats["all"]["observe_ms"])), 1)
    return table, line


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10, help="dev seeds 0 … N−1 per task")
    parser.add_argument("--tasks", default="all", help="comma-separated task names or 'all'")
    parser.add_argument("--split", default="seen", help="attribute split of the scenes")
    args = parser.parse_args()
    console = Console(stderr=True)
    tasks = list(TASKS) if args.tasks == "all" else args.tasks.split(",")
    world = TabletopWorld()
    def new() -> dict[str, dict[str, list[float]]]:
        return defaultdict(lambda: defaultdict(list))

    by_state = {"reset": new(), "reach": new()}
    pooled = new()
    scenes = 0
    for name in tasks:
        for seed in range(args.seeds):
            setup = reset_episode(TASKS[name], world, args.split, seed)
            for state in ("reset", "reach"):
                if state == "reach" and not reach(world, setup.attributes):
                    continue
                score_scene(world, by_state[state])
                score_scene(world, pooled)
            scenes += 1
    for state, stats in by_state.items():
        console.print(summarise(stats, f"colour-depth vs ground truth, arm {state}")[0])
    line = summarise(pooled, "pooled")[1]
    line["scenes"] = scenes
    print(" ".join(f"{k}={v}" for k, v in line.items()))


if __name__ == "__main__":
    main()
