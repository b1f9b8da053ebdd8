"""Planner speed: cost-map post-processing, global path search and trajectory extraction at 100³.

Scenes (1 m cube, 100³ voxels, an object to avoid, rotation/velocity/gripper maps), drawn per
seed from :mod:`voxposer.planning.obstacle_scenes`: "cup" (a cup-shaped obstacle right in front
of the target, random blobs), "wall" (a wall with one 12 cm gap), "enclosed" (the target in a
box open on one side) and "sealed" (the box closed: the planner must report the target
unreachable). The global planner runs on all of them, the paper's greedy planner on the cups.
Figures are medians over the runs; "post+search" is the planner's cost-map post-processing and
path search together. The last line is machine-readable.

    python benchmarks/planner.py [--runs 20]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from rich.console import Console
from rich.progress import track
from rich.table import Table

from voxposer.errors import TargetUnreachableError
from voxposer.planning import PathPlanner, PlannerConfig
from voxposer.planning.obstacle_scenes import make_scene

REACHABLE = ("cup", "wall", "enclosed")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=20, help="scenes per kind")
    args = parser.parse_args()
    console = Console(stderr=True)
    scenes = [(kind, make_scene(kind, np.random.default_rng(seed)))
              for kind in (*REACHABLE, "sealed") for seed in range(args.runs)]
    grid = scenes[0][1].grid
    planners = {m: PathPlanner(grid, PlannerConfig(method=m)) for m in ("global", "greedy")}

    def plan(method: str, scene):
        return planners[method].plan(
            scene.affordance_map, scene.start, avoidance_map=scene.avoidance_map,
            rotation_map=scene.rotation_map, velocity_map=scene.velocity_map,
            gripper_map=scene.gripper_map, occupancy=scene.occupancy)

    plan("global", scenes[0][1])  # warm-up: loads (or compiles) the search kernel
    rows: dict[str, list[dict[str, float]]] = {k: [] for k in (*REACHABLE, "greedy")}
    reached = {k: 0 for k in rows}
    unreachable_ms: list[float] = []
    errors: list[float] = []
    for kind, scene in track(scenes, description="planning", console=console):
        if kind == "sealed":
            t0 = time.perf_counter()
            try:
                plan("global", scene)
            except TargetUnreachableError:
                unreachable_ms.append((time.perf_counter() - t0) * 1e3)
            continue
        result = plan("global", scene)
        rows[kind].append(result.timings_ms)
        reached[kind] += int(result.reached)
        errors.append(float(np.linalg.norm(result.target - scene.target)))
        if kind == "cup":
            greedy = plan("greedy", scene)
            rows["greedy"].append(greedy.timings_ms)
            reached["greedy"] += int(greedy.reached)

    def med(timings: list[dict[str, float]], key: str) -> float:
        if key == "post+search":
            return float(np.median([t["postprocess"] + t["search"] for t in timings]))
        return float(np.median([t[key] for t in timings]))

    keys = ("postprocess", "search", "post+search", "trajectory", "total")
    table = Table(title=f"planner, 100³ voxels, {args.runs} scenes per kind, "
                        f"{os.cpu_count()} CPU cores (medians, ms)")
    for col in ("scenes", *keys, "reached"):
        table.add_column(col, justify="right")
    every = [t for k in REACHABLE for t in rows[k]]
    for name, timings in [*((k, rows[k]) for k in REACHABLE), ("all reachable", every),
                          ("cup, greedy", rows["greedy"])]:
        got = sum(reached[k] for k in REACHABLE) if name == "all reachable" else \
            reached["greedy" if name == "cup, greedy" else name]
        table.add_row(name, *(f"{med(timings, k):.1f}" for k in keys), f"{got}/{len(timings)}")
    console.print(table)
    sealed = f"{np.median(unreachable_ms):.1f}" if unreachable_ms else "nan"
    console.print(f"sealed target reported unreachable in {len(unreachable_ms)}/{args.runs} "
                  f"scenes, median {sealed} ms (max "
                  f"{max(unreachable_ms) if unreachable_ms else float('nan'):.1f} ms)")
    console.print(f"global end-point error: max {max(errors) * 100:.2f} cm")
    cup, greedy = med(rows["cup"], "total"), med(rows["greedy"], "total")
    print(
        f"post_search_ms={med(every, 'post+search'):.2f} "
        f"postprocess_ms={med(every, 'postprocess'):.2f} search_ms={med(every, 'search'):.2f} "
        f"total_ms={med(every, 'total'):.2f} unreachable_ms={sealed} "
        f"unreachable_reported={len(unreachable_ms)}/{args.runs} "
        f"cup_total_ms={cup:.2f} greedy_total_ms={greedy:.2f} speedup={greedy / cup:.1f} "
        f"greedy_reached={reached['greedy']} reached={sum(reached[k] for k in REACHABLE)}"
        f"/{len(every)}"
    )


if __name__ == "__main__":
    main()
