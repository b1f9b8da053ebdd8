"""Perception per replanning step: observing (rendering, sensor noise, registration) and
labelling the fused cloud, as the closed loop pays them every 0.2 s of simulated time.

A tabletop scene (two blocks) is observed through :class:`voxposer.pipeline.Embodiment`'s
perceiver for ``--perception``; between steps the physics advances 0.2 s (a 5 Hz replan). With
``--camera-hz`` each camera streams at its own rate (``CameraConfig.frame_hz``: at 2.5 Hz two
of the four views are new at each step, and a view not renewed is neither noised, lifted nor
classified again). With ``--track-labels`` the pixel perception detects at most once a second
and carries the labels in between (:mod:`voxposer.perception.label_tracking`); ``carried`` is
the share of steps whose labels were carried. Medians over ``--steps`` steps after a first one
(which registers the cameras). The last line is machine-readable.

    python benchmarks/perception_step.py [--perception colour-depth-noisy] [--camera-hz 2.5]
                                         [--steps 16] [--track-labels]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import numpy as np

from voxposer.envs import SceneLayout, TabletopWorld, WorldConfig
from voxposer.perception.label_tracking import LabelTrackingConfig
from voxposer.pipeline import PERCEPTIONS, Embodiment


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--perception", choices=PERCEPTIONS, default="colour-depth-noisy")
    parser.add_argument("--camera-hz", type=float, default=None,
                        help="each camera's frame rate in simulated time [Hz] (default: every "
                        "camera at every step)")
    parser.add_argument("--steps", type=int, default=16, help="steps timed")
    parser.add_argument("--track-labels", action="store_true",
                        help="carry the pixel labels between detections (colour-depth "
                        "perceptions: voxposer.perception.label_tracking, its defaults)")
    args = parser.parse_args()
    tracking = LabelTrackingConfig() if args.track_labels else None
    config = WorldConfig()
    world = TabletopWorld(replace(config, cameras=replace(config.cameras,
                                                          frame_hz=args.camera_hz)))
    body = Embodiment.simulated(world, args.perception, tracking=tracking)
    world.reset(np.random.default_rng(0), SceneLayout(blocks=("blue", "green")))
    perceiver = body.perceiver
    perceiver.point_cloud()
    observe, label = [], []
    for _ in range(args.steps):
        world.advance(round(0.2 / world.model.opt.timestep))
        t0 = time.perf_counter()
        perceiver.observe()
        t1 = time.perf_counter()
        perceiver.point_cloud()
        t2 = time.perf_counter()
        observe.append((t1 - t0) * 1e3)
        label.append((t2 - t1) * 1e3)
    total = np.add(observe, label)
    flags = getattr(perceiver, "carried", [])[1:]
    carried = float(np.mean(flags)) if flags else 0.0
    print(f"perception={args.perception} camera_hz={args.camera_hz} "
          f"track_labels={int(args.track_labels)} "
          f"observe_ms={np.median(observe):.1f} label_ms={np.median(label):.1f} "
          f"step_ms={np.median(total):.1f} carried={carried:.2f}")


if __name__ == "__main__":
    main()
