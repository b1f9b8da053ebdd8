"""The learning loop on the real door: a zero-shot τ₀ from the reference program, a tiny budget,
a model that predicts held-out transitions better after more data, and resume from the JSONL."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from voxposer.envs.articulated import ArticulatedWorld
from voxposer.learning.loop import LearnConfig, RunSpec, run_learning
from voxposer.learning.policies import LearningPolicy, stage_orientations
from voxposer.learning.record import record_zero_shot
from voxposer.learning.reference import INSTRUCTIONS, reference_backend
from voxposer.learning.rollout import Episode, RolloutConfig, run_episode
from voxposer.learning.state import StateObserver, layout_for
from voxposer.learning.task_cost import TaskCost
from voxposer.learning.zero_shot import ZeroShotTrajectory
from voxposer.perception.segmentation import SegmentationPerceiver
from voxposer.planning.dynamics.mlp import MLPConfig, MLPDynamics


@pytest.fixture(scope="module")
def door() -> tuple[ArticulatedWorld, StateObserver, ZeroShotTrajectory]:
    world = ArticulatedWorld("door")
    observer = StateObserver(layout_for("door"), world, SegmentationPerceiver(world, world.grid))
    traj = record_zero_shot(world, reference_backend("door"), INSTRUCTIONS["door"], task="door",
                            source="reference", seed=0, period_s=0.25)
    return world, observer, traj


def _error(model: MLPDynamics, episode: Episode) -> float:
    """Mean squared one-step prediction error over an episode's transitions."""
    predicted = model.predict(episode.obs[:-1], episode.actions)
    return float(((predicted - episode.obs[1:]) ** 2).sum(axis=1).mean())


def test_zero_shot_run_leaves_its_waypoints_and_maps(
        door: tuple[ArticulatedWorld, StateObserver, ZeroShotTrajectory]) -> None:
    _, _, traj = door
    assert [s.subtask for s in traj.stages][:2] == ["grasp the door handle",
                                                   "press the door handle down by 3cm"]
    assert traj.stages[0].entity == "gripper" and traj.stages[1].gripper == 1.0
    assert len(traj.waypoints) > 10 and np.all(np.diff(traj.stage_of) >= 0)
    # the hand went to the handle: some waypoint is within 3 cm of it
    handle = door[0].part_position("door handle")
    assert np.linalg.norm(traj.waypoints - handle, axis=1).min() < 0.05


def test_learning_improves_prediction_and_resumes(
        door: tuple[ArticulatedWorld, StateObserver, ZeroShotTrajectory], tmp_path: Path) -> None:
    world, observer, traj = door
    cfg = LearnConfig(time_limit_s=1.0, episodes_per_iteration=1, eval_episodes=1,
                      epochs_per_iteration=40, n_samples=200, horizon=3,
                      rollout=RolloutConfig(max_steps=20), mlp=MLPConfig(hidden_sizes=(64, 64)))
    spec = RunSpec("door", True, 0)
    first = run_learning(spec, cfg, [traj], lambda task: (world, observer), tmp_path)
    assert len(first) == 1 and first[0]["stopped"] == "time limit"
    early = MLPDynamics.from_file(spec.folder(tmp_path) / "model.npz")
    log = spec.folder(tmp_path) / "iterations.jsonl"
    line = json.loads(log.read_text())
    for key in ("final", "stopped", "converged"):
        del line[key]  # as if it had been stopped after its first iteration
    log.write_text(json.dumps(line) + "\n")
    later = run_learning(spec, replace(cfg, time_limit_s=20.0), [traj],
                         lambda task: (world, observer), tmp_path)
    assert [r["iteration"] for r in later] == list(range(len(later))) and len(later) >= 3
    assert later[0]["transitions"] == first[0]["transitions"]
    assert later[-1]["transitions"] > 2 * first[0]["transitions"]
    assert later[-1]["interaction_s"] >= 20.0
    late = MLPDynamics.from_file(spec.folder(tmp_path) / "model.npz")
    # a held-out episode around τ₀ (another seed, never trained on)
    cost = TaskCost(traj.stages, observer.layout)
    policy = LearningPolicy(cost, cfg.mpc(), traj, stage_orientations(traj))
    world.reset(np.random.default_rng(99))
    held = run_episode(world, observer, policy, cost, RolloutConfig(max_steps=20),
                       np.random.default_rng(99))
    assert _error(late, held) < _error(early, held)
