"""Benchmark of the tabletop world: physics speed, observation cost, IK cost.

Prints medians and ends with one machine-readable line:
``physics_rtf=<sim s per wall s> obs_320_ms=<ms> obs_640_ms=<ms> ik_ms=<ms>``.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import statistics
import time

import numpy as np

from voxposer.envs import TOP_DOWN_QUAT, TabletopWorld
from voxposer.envs.controller import xyzw_to_wxyz
from voxposer.envs.ik import HOME_Q


def _median_ms(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append((time.perf_counter() - start) * 1000.0)
    return statistics.median(times)


def main() -> None:
    world = TabletopWorld()
    world.reset(np.random.default_rng(0))
    steps = 1000
    rtfs = []
    for _ in range(3):
        start = time.perf_counter()
        world.advance(steps)
        rtfs.append(steps * world.config.timestep / (time.perf_counter() - start))
    rtf = statistics.median(rtfs)
    print(f"physics: {rtf:.1f}x real time ({world.model.nv} dofs, dt {world.config.timestep} s)")

    def observe(w: int, h: int) -> None:
        world.advance(1)  # invalidate the cache
        world.observe(w, h)

    observe(320, 240)
    obs320 = _median_ms(lambda: observe(320, 240), 7)
    obs640 = _median_ms(lambda: observe(640, 480), 5)
    print(f"observe (4 cameras RGB+depth+ids + fused cloud): 320x240 {obs320:.1f} ms, "
          f"640x480 {obs640:.1f} ms")

    rng = np.random.default_rng(1)
    targets = [np.array([rng.uniform(-0.3, 0.1), rng.uniform(-0.3, 0.3), rng.uniform(0.05, 0.4)])
               for _ in range(30)]
    quat = xyzw_to_wxyz(TOP_DOWN_QUAT)
    it = iter(targets)
    ik = _median_ms(lambda: world.ik.solve(next(it), quat, HOME_Q, restarts=4, rng=rng), 30)
    print(f"IK one-off solve from the home pose: {ik:.2f} ms")
    world.close()
    print(f"physics_rtf={rtf:.1f} obs_320_ms={obs320:.1f} obs_640_ms={obs640:.1f} ik_ms={ik:.2f}")


if __name__ == "__main__":
    main()
