"""Simulated pushing transitions for the learned push model."""

from __future__ import annotations

import numpy as np

from voxposer.bench.push_data import collect_pushes, heuristic_errors


def test_simulated_pushes_move_blocks_along_the_push(world) -> None:
    seen: list[int] = []
    t = collect_pushes(world, 24, np.random.default_rng(0), per_scene=12, on_scene=seen.append)
    assert len(t) == 24 and seen == [12, 24]
    assert np.all(t.obs == 0.0)
    lateral, depth, distance, incidence = t.actions.T
    assert np.all(np.abs(lateral) <= 0.03)  # within half the block's width
    assert np.all((distance >= 0.01) & (distance <= 0.08))
    assert np.all(np.abs(incidence) <= np.pi / 4 + 1e-9)
    assert np.all((depth < -0.015) & (depth > -0.045))  # contacts on the rear face
    along = t.next_obs[:, 0]
    assert np.mean(along > 0.3 * distance) > 0.8  # pushed forward, roughly by the distance
    assert np.corrcoef(along, distance)[0, 1] > 0.8
    # the heuristic (translation by the distance) is not exact: friction, yaw, the contact gap
    errors = heuristic_errors(t)
    assert errors["centre_median_m"] > 0.0005
