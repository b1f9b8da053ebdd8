"""Recording zero-shot trajectories: VoxPoser opens the object once, τ₀ and its maps are kept.

The instruction runs through the same pipeline as ``voxposer run`` (planner → composer → value
maps → planner and closed-loop executor, :func:`voxposer.pipeline.voxposer_runtime`) on an
articulated world. While it runs, the end effector's pose and the gripper command are sampled
every control period and resampled into waypoints a few centimetres apart (:func:`resample`);
every executed sub-task leaves its entity and the cost map its first plan searched (:class:`~voxposer.learning.zero_shot.Stage`).
"""

from __future__ import annotations

import logging
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from voxposer.control.config import ExecutorConfig
from voxposer.errors import ConfigError, VoxPoserError
from voxposer.learning.state import StateObserver, layout_for
from voxposer.learning.zero_shot import Stage, ZeroShotTrajectory
from voxposer.lmp.backends.base import LLMBackend
from voxposer.pipeline import Embodiment, voxposer_runtime

log = logging.getLogger(__name__)

#: The executor of zero-shot runs: as the tabletop's, but a target counts as reached within
#: 8 mm, not 2 cm — a handle bar 2 cm thick is missed by a grasp 2 cm off.
ZERO_SHOT_EXECUTOR: Final = ExecutorConfig(reach_tolerance_m=0.008)


class _Sampler:
    """A world step callback keeping (position, quaternion, gripper, sub-task index) every
    ``period_s`` of simulated time."""

    def __init__(self, period_s: float, running: Any) -> None:
        self.period_s = period_s
        self.running = running  # () -> index of the sub-task running now
        self.next_time = -np.inf
        self.rows: list[tuple[NDArray[np.float64], NDArray[np.float64], float, int]] = []

    def __call__(self, world: Any) -> None:
        if world.time + 1e-9 < self.next_time:
            return
        pos, quat = world.get_ee_pose()
        self.rows.append((np.array(pos), np.array(quat), float(world.get_gripper_state()),
                          int(self.running())))
        self.next_time = world.time + self.period_s


def resample(rows: list[tuple[NDArray[np.float64], NDArray[np.float64], float, int]],
             spacing_m: float) -> list[tuple[NDArray[np.float64], NDArray[np.float64], float, int]]:
    """Waypoints at most ``spacing_m`` apart along the sampled path [m], keeping every change of
    the gripper command or of the sub-task (a change is held for one extra waypoint, so that the
    fingers settle before the hand moves on)."""
    out = [rows[0]]
    for row in rows[1:]:
        last = out[-1]
        changed = row[2] != last[2] or row[3] != last[3]
        gap = float(np.linalg.norm(row[0] - last[0]))
        if gap >= spacing_m:
            pieces = int(np.ceil(gap / spacing_m))
            for k in range(1, pieces):  # a fast stretch of the run, cut into reachable steps
                f = k / pieces
                out.append((last[0] + f * (row[0] - last[0]), row[1], last[2], last[3]))
            out.append(row)
            if changed:
                out.append(row)
        elif changed:
            out += [row, row]
    if out[-1] is not rows[-1]:
        out.append(rows[-1])
    return out


def _stages(records: list[Any], rows: list[tuple[Any, Any, float, int]]
            ) -> tuple[tuple[Stage, ...], dict[int, int]]:
    """Stages of the executed sub-tasks that planned, and record index → stage index."""
    stages: list[Stage] = []
    index: dict[int, int] = {}
    for k, rec in enumerate(records):
        plan = rec.result.first_plan
        if plan is None:
            continue
        grips = [g for (_, _, g, i) in rows if i == k]
        cm = plan.cost_map
        index[k] = len(stages)
        stages.append(Stage(subtask=rec.subtask, entity=rec.result.entity, grid=cm.grid,
                            cost=np.asarray(cm.cost, dtype=np.float32),
                            target_distance=np.asarray(cm.target_distance, dtype=np.float32),
                            gripper=float(np.median(grips)) if grips else 0.0,
                            reached=bool(rec.result.success)))
    return tuple(stages), index


def record_zero_shot(world: Any, backend: LLMBackend, instruction: str, *, task: str,
                     source: str, seed: int, period_s: float,
                     spacing_m: float = 0.02,
                     executor: ExecutorConfig | None = None) -> ZeroShotTrajectory:
    """Reset ``world`` with ``seed``, run ``instruction`` zero-shot, return τ₀ and its stages.

    Args:
        world: an articulated world (robot, observation source with ``grid``, ``success()``,
            ``step_callbacks``).
        backend: who writes the programs (the reference programs' replay, or a model).
        instruction: e.g. "open the door".
        task: the task name stored with the trajectory.
        source: "reference" or the model's name.
        seed: the episode seed (reset and the executor's randomness).
        period_s: the learner's action period [s] (stored with the trajectory).
        spacing_m: largest distance between two waypoints [m]: the end effector is sampled
            every control period and the path resampled (:func:`resample`).
        executor: the closed-loop executor's parameters (default: :data:`ZERO_SHOT_EXECUTOR`).

    Raises:
        ConfigError: nothing was executed (no sub-task planned), so there is no task cost.
    """
    rng = np.random.default_rng(seed)
    world.reset(rng)
    body = Embodiment.simulated(world, "ground-truth")
    start = StateObserver(layout_for(task), world, body.perceiver)
    start.reset()
    handle_start = start.observe()[4:7]  # where τ₀ and its maps are anchored (perceived, as o_0)
    runtime, handoff = voxposer_runtime(body, backend, rng,
                                        executor_config=executor or ZERO_SHOT_EXECUTOR)
    handoff.keep_going = True  # τ₀ is the whole program, as the paper's open-loop chain
    sampler = _Sampler(world.control_period, lambda: len(handoff.records))
    world.step_callbacks.append(sampler)
    try:
        runtime.run(instruction)
    except VoxPoserError as exc:  # a failed zero-shot run still leaves its trajectory
        log.info("zero-shot %s seed %d stopped: %s", task, seed, exc)
    finally:
        world.step_callbacks.remove(sampler)
        sampler(world)
    stages, index = _stages(handoff.records, sampler.rows)
    rows = resample(sampler.rows, spacing_m) if sampler.rows else []
    if not stages or len(rows) < 2:
        raise ConfigError(f"the zero-shot run of {instruction!r} (seed {seed}) executed no "
                          "planned sub-task: no trajectory or task cost to learn from")
    last = max(index.values())
    stage_of = np.array([index.get(i, min(last, max([v for k, v in index.items() if k <= i],
                                                      default=0)))
                         for (_, _, _, i) in rows], dtype=np.int64)
    success, reason = world.success()
    log.info("zero-shot %s seed %d: %s", task, seed, reason)
    return ZeroShotTrajectory(
        task=task, source=source, seed=seed,
        waypoints=np.array([r[0] for r in rows]), quats=np.array([r[1] for r in rows]),
        gripper=np.array([r[2] for r in rows]), stage_of=stage_of,
        period_s=period_s, success=bool(success), stages=stages, handle_start=handle_start)


__all__ = ["ZERO_SHOT_EXECUTOR", "record_zero_shot", "resample"]
