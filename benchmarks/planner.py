"""Planner speed: cost-map post-processing, global path search and trajectory extraction at 100³.

Scenes: the built-in synthetic scene (1 m cube, 100³ voxels, a cup-shaped obstacle right in
front of the target, random obstacle blobs, an object to avoid, rotation/velocity/gripper maps),
one per seed. The global planner and the paper's greedy planner run on the same scenes; the
figures are medians over the runs. The last line is machine-readable.

    python benchmarks/planner.py [--runs 20]
"""

from __future__ import annotations

import argparse
import os

import numpy as np
from rich.console import Console
from rich.progress import track
from rich.table import Table

from voxposer.planning import PathPlanner, PlannerConfig
from voxposer.planning.synthetic_scene import make_synthetic_scene


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=20, help="scenes (one plan each per method)")
    args = parser.parse_args()
    console = Console(stderr=True)
    scenes = [make_synthetic_scene(np.random.default_rng(seed)) for seed in range(args.runs)]
    planners = {
        m: PathPlanner(scenes[0].grid, PlannerConfig(method=m)) for m in ("global", "greedy")
    }

    def plan(method: str, scene):
        return planners[method].plan(
            scene.affordance_map,
            scene.start,
            avoidance_map=scene.avoidance_map,
            rotation_map=scene.rotation_map,
            velocity_map=scene.velocity_map,
            gripper_map=scene.gripper_map,
            occupancy=scene.occupancy,
        )

    plan("global", scenes[0])  # warm-up: loads (or compiles) the search kernel
    timings: dict[str, list[dict[str, float]]] = {"global": [], "greedy": []}
    reached: dict[str, list[bool]] = {"global": [], "greedy": []}
    errors: list[float] = []
    for scene in track(scenes, description="planning", console=console):
        for method in ("global", "greedy"):
            result = plan(method, scene)
            timings[method].append(result.timings_ms)
            reached[method].append(result.reached)
            if method == "global":
                errors.append(float(np.linalg.norm(result.target - scene.target)))

    def med(method: str, key: str) -> float:
        return float(np.median([t[key] for t in timings[method]]))

    table = Table(
        title=f"planner, 100³ voxels, {args.runs} scenes, {os.cpu_count()} CPU cores (medians)"
    )
    for col in ("planner", "postprocess ms", "search ms", "trajectory ms", "total ms", "reached"):
        table.add_column(col, justify="right")
    for method in ("global", "greedy"):
        table.add_row(
            method,
            *(f"{med(method, k):.1f}" for k in ("postprocess", "search", "trajectory", "total")),
            f"{sum(reached[method])}/{len(reached[method])}",
        )
    console.print(table)
    console.print(f"global end-point error: max {max(errors) * 100:.2f} cm")
    total, greedy_total = med("global", "total"), med("greedy", "total")
    print(
        f"postprocess_ms={med('global', 'postprocess'):.2f} search_ms={med('global', 'search'):.2f} "
        f"total_ms={total:.2f} greedy_total_ms={greedy_total:.2f} "
        f"speedup={greedy_total / total:.1f} greedy_reached={int(any(reached['greedy']))} "
        f"reached={int(all(reached['global']))}"
    )


if __name__ == "__main__":
    main()
