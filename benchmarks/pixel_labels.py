"""Pixel perception speed: labelling one observation from RGB-D alone (colour words, fusion,
blocks and lines, the cabinet fit, table, robot and gripper).

Renders the 4 cameras of a tabletop scene (three blocks, the cabinet), optionally through the
consumer RGB-D noise model, and times :func:`voxposer.perception.pixel_labels.label_pixels` on
``--frames`` observations, each after a physics step (a new observation, as at every replan).
Rendering and noise are not timed. The last line is machine-readable.

    python benchmarks/pixel_labels.py [--frames 10] [--noisy]
"""

from __future__ import annotations

import argparse
import time

import mujoco
import numpy as np

from voxposer.envs import SceneLayout, TabletopWorld
from voxposer.perception.noisy_source import NoisyObservationSource
from voxposer.perception.pixel_labels import label_pixels
from voxposer.perception.sensor_noise import SensorNoiseConfig


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=10, help="observations timed")
    parser.add_argument("--noisy", action="store_true", help="through the RGB-D noise model")
    args = parser.parse_args()
    world = TabletopWorld()
    world.reset(np.random.default_rng(3), SceneLayout(blocks=("blue", "red", "gray"),
                                                      cabinet=True))
    source = (NoisyObservationSource(world, SensorNoiseConfig(), 3) if args.noisy else world)
    times, points = [], 0
    for k in range(args.frames + 1):
        mujoco.mj_step(world.model, world.data)
        obs = source.observe(rgb=True)
        t0 = time.perf_counter()
        labels = label_pixels(obs, world.grid)
        if k:  # the first frame warms up
            times.append((time.perf_counter() - t0) * 1e3)
        points = len(labels.cloud.points)
    ms = float(np.median(times))
    print(f"{args.frames} observations, {points} points each, median {ms:.1f} ms per labelling")
    print(f"noisy={args.noisy} label_ms={ms:.2f} points={points}")


if __name__ == "__main__":
    main()
