"""The learning loop on the toy door double: records, resume, a model that learns, both arms."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from voxposer.errors import ConfigError
from voxposer.learning.loop import LearnConfig, RunSpec, run_learning
from voxposer.learning.policies import LearningPolicy, stage_orientations
from voxposer.learning.rollout import RolloutConfig, run_episode
from voxposer.learning.task_cost import TaskCost
from voxposer.planning.dynamics.mlp import MLPConfig

from .toy_door import ToyDoor, ToyObserver, trajectory


def _world(task: str) -> tuple[ToyDoor, ToyObserver]:
    door = ToyDoor()
    return door, ToyObserver(door)


def _config(limit: float = 12.0) -> LearnConfig:
    return LearnConfig(time_limit_s=limit, episodes_per_iteration=1, eval_episodes=1,
                       epochs_per_iteration=20, n_samples=200, horizon=3,
                       rollout=RolloutConfig(step_duration_s=0.25, max_steps=24),
                       mlp=MLPConfig(hidden_sizes=(32, 32)), converged_success=1.1)


def test_prior_episode_follows_the_zero_shot_waypoints() -> None:
    door, observer = _world("door")
    traj = trajectory()
    cost = TaskCost(traj.stages, observer.layout)
    policy = LearningPolicy(cost, _config().mpc(), traj, stage_orientations(traj))
    ep = run_episode(door, observer, policy, cost, RolloutConfig(max_steps=10),
                     np.random.default_rng(1))
    # after 10 actions around τ₀ the hand is near τ₀'s 11th waypoint (the handle), not at home
    assert np.linalg.norm(ep.obs[-1, :3] - traj.waypoints[10]) < 0.04
    assert ep.actions.shape == (10, 4) and ep.obs.shape == (11, 9)
    assert ep.sim_time_s == pytest.approx(10 * 0.25)


def test_uniform_episode_stays_in_the_action_box() -> None:
    door, observer = _world("door")
    traj = trajectory()
    cost = TaskCost(traj.stages, observer.layout)
    policy = LearningPolicy(cost, _config().mpc(), None, stage_orientations(traj))
    ep = run_episode(door, observer, policy, cost, RolloutConfig(max_steps=30),
                     np.random.default_rng(2))
    assert np.abs(ep.actions[:, :3]).max() <= 0.03 + 1e-12
    assert ep.actions[:, 3].min() >= 0 and ep.actions[:, 3].max() <= 1
    assert np.abs(ep.actions[:, :3]).max() > 0.02  # it does cover the box


def test_run_writes_a_line_per_iteration_and_stops_at_the_limit(tmp_path: Path) -> None:
    records = run_learning(RunSpec("door", True, 0), _config(), [trajectory()], _world, tmp_path)
    lines = (tmp_path / "door" / "prior-on" / "seed-0" / "iterations.jsonl").read_text()
    assert [json.loads(x)["iteration"] for x in lines.splitlines()] == list(range(len(records)))
    assert records[-1]["final"] and records[-1]["stopped"] == "time limit"
    assert records[-1]["interaction_s"] >= 12.0
    assert records[-2]["interaction_s"] < 12.0  # it stopped at the first iteration past it
    assert records[-1]["transitions"] >= 48  # two episodes of 24 actions at least


def test_resume_continues_after_the_last_line(tmp_path: Path) -> None:
    spec, cfg = RunSpec("door", True, 0), _config(limit=18.0)
    full = run_learning(spec, cfg, [trajectory()], _world, tmp_path / "full")
    part = tmp_path / "part"
    short = run_learning(spec, _config(limit=6.0), [trajectory()], _world, part)
    log = spec.folder(part) / "iterations.jsonl"
    lines = log.read_text().splitlines()
    last = json.loads(lines[-1])
    del last["final"], last["stopped"], last["converged"]  # as if stopped before the end
    log.write_text("\n".join([*lines[:-1], json.dumps(last)]) + "\n")
    resumed = run_learning(spec, cfg, [trajectory()], _world, part)
    assert len(short) < len(resumed) == len(full)
    assert [r["transitions"] for r in resumed] == [r["transitions"] for r in full]


def test_model_prediction_improves_over_the_first_iteration(tmp_path: Path) -> None:
    records = run_learning(RunSpec("door", True, 1), _config(limit=30.0), [trajectory()],
                           _world, tmp_path)
    held = [r["held_out_loss"] for r in records if r["held_out_loss"] is not None]
    assert len(held) >= 3
    assert held[-1] < 0.5 * held[0]


def test_without_prior_samples_uniformly_and_writes_its_own_folder(tmp_path: Path) -> None:
    records = run_learning(RunSpec("door", False, 0), _config(limit=6.0), [trajectory()],
                           _world, tmp_path)
    assert (tmp_path / "door" / "prior-off" / "seed-0" / "model.npz").exists()
    assert records[-1]["prior"] is False


def test_no_zero_shot_trajectory_is_one_clear_error(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="no zero-shot trajectory of task 'window'"):
        run_learning(RunSpec("window", True, 0), _config(), [trajectory()], _world, tmp_path)


def test_bad_config_names_the_field() -> None:
    with pytest.raises(ConfigError, match="time limit"):
        LearnConfig(time_limit_s=0)
    with pytest.raises(ConfigError, match="eval_episodes"):
        LearnConfig(eval_episodes=0)


class _Drift:
    """Always 3 cm toward +y, gripper open (a policy double)."""

    def act(self, obs, step, stage, rng):  # type: ignore[no-untyped-def]
        return np.array([0.0, 0.03, 0.0, 0.0]), np.array([0.0, 0.0, 0.0, 1.0])

    def stage_at(self, step: int) -> int:
        return 0


def test_targets_off_the_workspace_are_clipped_and_the_episode_goes_on() -> None:
    door, observer = _world("door")
    cost = TaskCost(trajectory().stages, observer.layout)
    ep = run_episode(door, observer, _Drift(), cost, RolloutConfig(max_steps=20),
                     np.random.default_rng(0))
    assert len(ep.actions) == 20
    assert ep.obs[-1, 1] == pytest.approx(door.grid.bounds_max[1] - 0.01)
