"""Learned-dynamics speed: one training epoch of the MLP on 10k transitions and one MPC step.

Synthetic door-like transitions (observation: end-effector position [m] (3), gripper, handle
angle [rad], door angle [rad]; action: end-effector displacement [m] (3) and gripper command)
train the default :class:`~voxposer.planning.dynamics.MLPDynamics` (2 × 128 ReLU, Adam, batch
256); the MPC samples 1,000 sequences of horizon 5 around a prior and rolls them out through it.
Figures are medians over the runs (CPU seconds of this process and wall seconds). The last line
is machine-readable. Targets on 2 cores: epoch <= 1 s, MPC step <= 50 ms.

BLAS runs single-threaded unless OPENBLAS_NUM_THREADS is set: at these sizes (256 × 128)
threading costs more than it gains, and on a busy machine far more (see
benchmarks/results/nn_library.txt).

    python benchmarks/dynamics_speed.py [--runs 10]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import time
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from rich.console import Console
from rich.table import Table

from voxposer.planning.dynamics import MLPConfig, MLPDynamics, Transitions, train
from voxposer.planning.waypoint_mpc import WaypointMPCConfig, plan_action

D_O, D_A, N, HORIZON, SAMPLES = 6, 4, 10_000, 5, 1000


def door_transitions(rng: np.random.Generator, n: int) -> Transitions:
    """n synthetic transitions of a hinged door with a handle (not physics; smooth, nonlinear)."""
    obs = np.column_stack([rng.uniform(-0.3, 0.3, (n, 3)), rng.uniform(0, 1, n),
                           rng.uniform(0, 0.8, n), rng.uniform(0, 1.5, n)])
    act = np.column_stack([rng.uniform(-0.03, 0.03, (n, 3)), rng.uniform(-1, 1, n)])
    nxt = obs.copy()
    nxt[:, :3] += act[:, :3]
    nxt[:, 3] = np.clip(obs[:, 3] + act[:, 3], 0, 1)
    pressed = np.clip(obs[:, 4] - 10 * act[:, 2] * (obs[:, 3] > 0.5), 0, 0.8)
    nxt[:, 4] = pressed
    nxt[:, 5] = obs[:, 5] + (pressed > 0.5) * 5 * np.maximum(-act[:, 0], 0)
    return Transitions(obs, act, nxt)


def door_cost(pred: NDArray[np.float64], actions: NDArray[np.float64]) -> NDArray[np.float64]:
    """Door angle below 1.2 rad at the end plus a small control effort; shape (N,)."""
    return np.abs(1.2 - pred[:, -1, 5]) + 0.1 * np.linalg.norm(actions[..., :3], axis=2).sum(1)


def timed(fn: Callable[[], object], runs: int) -> tuple[float, float]:
    """Median (CPU s, wall s) of ``runs`` calls."""
    cpu, wall = [], []
    for _ in range(runs):
        c, w = time.process_time(), time.perf_counter()
        fn()
        cpu.append(time.process_time() - c)
        wall.append(time.perf_counter() - w)
    return float(np.median(cpu)), float(np.median(wall))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10, help="timed repetitions of each")
    args = parser.parse_args()
    console = Console(stderr=True)
    rng = np.random.default_rng(0)
    data = door_transitions(rng, N)
    model = MLPDynamics(D_O, D_A, MLPConfig(), np.random.default_rng(1))
    report = train(model, data, rng, 1)  # warm-up; fits the normaliser
    epoch_cpu, epoch_wall = timed(lambda: train(model, data, rng, 1), args.runs)

    cfg = WaypointMPCConfig(action_low=(-0.03, -0.03, -0.03, -1.0),
                            action_high=(0.03, 0.03, 0.03, 1.0),
                            n_samples=SAMPLES, horizon=HORIZON, sigma=0.005)
    obs = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0])
    prior = np.tile([-0.02, 0.0, -0.01, 0.0], (HORIZON, 1))
    plan_action(model, obs, door_cost, rng, cfg, prior)  # warm-up
    mpc_cpu, mpc_wall = timed(lambda: plan_action(model, obs, door_cost, rng, cfg, prior),
                              args.runs)

    threads = os.environ.get("OPENBLAS_NUM_THREADS")
    table = Table(title=f"learned dynamics, {os.cpu_count()} CPU cores, BLAS threads {threads}, "
                        f"{args.runs} runs (medians)")
    for col in ("what", "CPU", "wall", "target"):
        table.add_column(col, justify="right")
    table.add_row(f"train epoch, {N} transitions, batch 256", f"{epoch_cpu:.3f} s",
                  f"{epoch_wall:.3f} s", "<= 1 s")
    table.add_row(f"MPC step, {SAMPLES} samples × H={HORIZON}", f"{mpc_cpu * 1e3:.1f} ms",
                  f"{mpc_wall * 1e3:.1f} ms", "<= 50 ms")
    console.print(table)
    console.print(f"first-epoch loss {report.losses[0]:.4f} (normalised MSE)")
    print(f"train_epoch_10k_s={epoch_wall:.3f} mpc_step_1000_ms={mpc_wall * 1e3:.1f}")


if __name__ == "__main__":
    main()
