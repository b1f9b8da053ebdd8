"""Closed-loop speed: replanning rate of a rollout and one random-shooting MPC step.

A rollout of "move to the top of the blue block while staying away from the green block" runs
with recorded programs (the replay backend, a test double for the LLM) in the MuJoCo world; every
replanning step observes the scene (4 RGB-D cameras at 320×240, fused cloud), re-runs the cached
programs to recompose the maps, and plans. ``replan_hz`` is the median number of such steps per
wall second (simulation of the robot's motion between steps not included). ``loop_hz`` is the
whole loop as ``voxposer run`` executes it: replanning steps per wall second with the
simulation, the rendering and the control between steps included (and ``realtime`` the simulated
seconds per wall second); the controller replans every 0.2 simulated seconds, so a loop of 10 Hz
runs at twice real time. ``shooting_ms`` is one random-shooting step with 10,000 sampled pushes
against a cost map. The last line is machine-readable.

    python benchmarks/closed_loop.py [--episodes 3] [--perception colour-depth-noisy]
                                     [--camera-hz 2.5] [--track-labels]

``--perception`` picks the perceiver (:data:`voxposer.pipeline.PERCEPTIONS`; default the
simulator's segmentation), e.g. the pixel perception with sensor noise. ``--camera-hz`` lets
each camera stream at its own rate in simulated time (``CameraConfig.frame_hz``: at 2.5 Hz two
of the four views are new at each 5 Hz replan, and a view not renewed is not lifted again);
default: all four views new at every replan. ``--track-labels`` lets the pixel perception
carry its labels between detections (:mod:`voxposer.perception.label_tracking`).
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from voxposer.envs import TabletopWorld
from voxposer.envs.config import WorldConfig
from voxposer.envs.layout import SceneLayout
from voxposer.lmp.backends.replay import ReplayBackend
from voxposer.perception.label_tracking import LabelTrackingConfig
from voxposer.pipeline import PERCEPTIONS, Embodiment, voxposer_runtime
from voxposer.planning.mpc import random_shooting
from voxposer.planning.push_primitive import PushConfig
from voxposer.valuemaps import compose_cost_map

RECORDINGS = Path(__file__).resolve().parents[1] / "tests/control/recordings/tabletop.jsonl"
INSTRUCTION = "move to the top of the blue block while staying away from the green block"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=3, help="rollouts (different seeds)")
    parser.add_argument("--perception", choices=PERCEPTIONS, default="ground-truth",
                        help="the perceiver of the rollouts")
    parser.add_argument("--camera-hz", type=float, default=None,
                        help="each camera's frame rate in simulated time [Hz] (default: every "
                        "camera at every observation)")
    parser.add_argument("--track-labels", action="store_true",
                        help="carry the pixel labels between detections (colour-depth "
                        "perceptions: voxposer.perception.label_tracking, its defaults)")
    args = parser.parse_args()
    tracking = LabelTrackingConfig() if args.track_labels else None
    console = Console(stderr=True)
    config = WorldConfig()
    world = TabletopWorld(replace(config, cameras=replace(config.cameras,
                                                          frame_hz=args.camera_hz)))
    body = Embodiment.simulated(world, args.perception, tracking=tracking)
    steps: list[dict[str, float]] = []
    successes, replans, wall_s, sim_s = 0, 0, 0.0, 0.0
    for seed in range(args.episodes):
        layout = SceneLayout(blocks=("blue", "green"), poses={"blue block": (0.0, -0.1 + 0.05 * seed),
                                                              "green block": (-0.12, -0.2)})
        world.reset(np.random.default_rng(seed), layout)
        runtime, executor = voxposer_runtime(body, ReplayBackend(RECORDINGS),
                                             np.random.default_rng(seed))
        with console.status(f"rollout {seed + 1}/{args.episodes}"):
            runtime.run(INSTRUCTION)
        result = executor.records[-1].result
        successes += result.success
        steps += result.timings_ms
        for record in executor.records:
            replans += record.result.replans
            wall_s += record.result.wall_time
            sim_s += record.result.sim_time

    # one random-shooting step: 10,000 pushes of the blue block toward a target
    world.reset(np.random.default_rng(0), SceneLayout(blocks=("blue",), poses={"blue block": (0.0, 0.0)}))
    block = body.perceiver.detect("blue block")
    grid = world.grid
    aff = np.zeros(grid.shape, np.float32)
    aff[tuple(grid.world_to_voxel(block.position + [0.15, 0.1, 0.0]))] = 1
    cmap = compose_cost_map(grid, aff, block.position, entity_occupancy=block.occupancy)
    path = block.position + np.linspace(0, 1, 20)[:, None] * np.array([0.15, 0.1, 0.0])
    rng = np.random.default_rng(0)
    cfg = PushConfig(n_samples=10_000)
    random_shooting(block.points, path, rng, cost_map=cmap, config=cfg)
    shots = []
    for _ in range(20):
        t0 = time.perf_counter()
        random_shooting(block.points, path, rng, cost_map=cmap, config=cfg)
        shots.append((time.perf_counter() - t0) * 1e3)

    parts = {k: float(np.median([s[k] for s in steps])) for k in ("observe", "maps", "plan")}
    per_step = np.array([sum(s.values()) for s in steps])
    hz = float(1000.0 / np.median(per_step))
    table = Table(title=f"closed loop, {os.cpu_count()} CPU cores, {args.perception} perception: "
                  f"{len(steps)} replanning steps in {args.episodes} rollouts ({successes} reached)")
    loop_hz, realtime = replans / wall_s, sim_s / wall_s
    for col in ("observe ms", "maps ms", "plan ms", "step ms", "replan Hz", "whole loop Hz",
                "x real time", "shooting ms (10k)"):
        table.add_column(col, justify="right")
    table.add_row(*(f"{parts[k]:.1f}" for k in ("observe", "maps", "plan")),
                  f"{np.median(per_step):.1f}", f"{hz:.1f}", f"{loop_hz:.1f}", f"{realtime:.2f}",
                  f"{np.median(shots):.1f}")
    console.print(table)
    print(f"perception={args.perception} camera_hz={args.camera_hz} "
          f"track_labels={int(args.track_labels)} replan_hz={hz:.2f} "
          f"loop_hz={loop_hz:.2f} realtime={realtime:.2f} shooting_ms={np.median(shots):.2f}")


if __name__ == "__main__":
    main()
