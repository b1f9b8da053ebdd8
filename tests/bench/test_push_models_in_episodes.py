"""The pushing MPC's dynamics model in benchmark episodes: the simulator and a learned model."""

from __future__ import annotations

import numpy as np

from voxposer.bench.episode import EpisodeJob, run_episode
from voxposer.planning.dynamics.mlp import MLPConfig, MLPDynamics
from voxposer.planning.dynamics.training import Transitions, train


def test_the_simulator_as_dynamics_model_pushes_the_block_to_its_place(world) -> None:
    rec = run_episode(EpisodeJob("push_to_pos", "seen", 0, seed_set="dev",
                                 dynamics="simulator"), world)
    assert rec.dynamics == "simulator"
    assert rec.push_predictions > 0, "the MPC sampled pushes through the simulator"
    assert rec.success, rec.reason


def test_a_learned_model_is_what_the_mpc_samples_through(world, tmp_path) -> None:
    # a stand-in law (the block moves by the push distance less 1 cm), learned by the MLP
    rng = np.random.default_rng(0)
    n = 500
    acts = np.column_stack([rng.uniform(-0.01, 0.01, n), np.full(n, -0.025),
                            rng.uniform(0.01, 0.08, n), rng.uniform(-0.7, 0.7, n)])
    mlp = MLPDynamics(3, 4, MLPConfig(hidden_sizes=(16,)), rng)
    outcome = np.column_stack([acts[:, 2] - 0.01, np.zeros(n), np.zeros(n)])
    train(mlp, Transitions(np.zeros((n, 3)), acts, outcome), rng, 20)
    path = tmp_path / "push_model.npz"
    mlp.save(path)
    rec = run_episode(EpisodeJob("push_to_pos", "seen", 0, seed_set="dev", dynamics="learned",
                                 push_model=str(path)), world)
    assert rec.dynamics == "learned" and rec.push_predictions > 0
    assert rec.error is None
    heuristic = run_episode(EpisodeJob("push_to_pos", "seen", 0, seed_set="dev"), world)
    assert heuristic.dynamics == "heuristic" and heuristic.success
