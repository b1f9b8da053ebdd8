"""The learned push model: features in the push's frame, a rigid predicted motion, and an MLP
that learns a known push law."""

from __future__ import annotations

import numpy as np
import pytest

from voxposer.errors import ConfigError
from voxposer.planning.dynamics import PushBatch
from voxposer.planning.dynamics.learned_push import (
    LearnedPush,
    face_normal_angle,
    push_actions,
    push_outcome,
)
from voxposer.planning.dynamics.mlp import MLPConfig, MLPDynamics
from voxposer.planning.dynamics.training import Transitions, train


def _square(yaw: float, centre=(0.0, 0.0, 0.025), half: float = 0.025) -> np.ndarray:
    t = np.linspace(-half, half, 11)
    edge = np.concatenate([np.column_stack([t, np.full(11, s * half)]) for s in (-1, 1)]
                          + [np.column_stack([np.full(11, s * half), t]) for s in (-1, 1)])
    c, s = np.cos(yaw), np.sin(yaw)
    xy = edge @ np.array([[c, s], [-s, c]])
    return np.column_stack([xy, np.zeros(len(xy))]) + np.asarray(centre)


def test_face_normal_of_a_turned_square_is_found_modulo_a_quarter_turn() -> None:
    for yaw in (0.0, 0.3, -0.6, 1.2):
        got = face_normal_angle(_square(yaw))
        assert abs((got - yaw + np.pi / 4) % (np.pi / 2) - np.pi / 4) < 0.02


def test_push_features_are_in_the_pushs_own_frame() -> None:
    points = _square(0.0, centre=(0.1, 0.2, 0.025))
    centre = points.mean(axis=0)
    pushes = PushBatch(np.array([[0.1, 0.175, 0.025], [0.125, 0.21, 0.025]]),
                       np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]), np.array([0.04, 0.02]))
    a = push_actions(centre, pushes, points)
    np.testing.assert_allclose(a[0], [0.0, -0.025, 0.04, 0.0], atol=1e-9)
    np.testing.assert_allclose(a[1], [-0.01, -0.025, 0.02, 0.0], atol=1e-9)  # s = (0, -1)
    np.testing.assert_allclose(push_outcome(centre, [0.0, 1.0, 0.0], centre + [0.01, 0.03, 0], 0.1),
                               [0.03, -0.01, 0.1], atol=1e-12)


def _law(actions: np.ndarray) -> np.ndarray:
    """A made-up push law: moves distance − 1 cm, drifts with the lateral offset, turns with it
    and with the incidence."""
    lat, _, dist, inc = actions.T
    return np.column_stack([dist - 0.01, 0.3 * lat, 8.0 * lat + 0.5 * inc])


def test_the_mlp_learns_a_known_push_law_and_predicts_it_rigidly() -> None:
    rng = np.random.default_rng(0)
    n = 3000
    acts = np.column_stack([rng.uniform(-0.012, 0.012, n), np.full(n, -0.025),
                            rng.uniform(0.01, 0.08, n), rng.uniform(-np.pi / 4, np.pi / 4, n)])
    mlp = MLPDynamics(3, 4, MLPConfig(hidden_sizes=(32, 32)), rng)
    train(mlp, Transitions(np.zeros((n, 3)), acts, _law(acts)), rng, 60)
    model = LearnedPush(mlp)
    points = _square(0.2)
    centre = points.mean(axis=0)
    k = 4
    d = np.array([[np.cos(0.4), np.sin(0.4), 0.0]] * k)  # 0.2 rad from the face normal
    side = np.array([-d[0, 1], d[0, 0], 0.0])
    lateral = np.array([-0.01, 0.0, 0.005, 0.01])
    contacts = centre - d * 0.025 + side * lateral[:, None]
    pushes = PushBatch(contacts, d, np.array([0.03, 0.05, 0.07, 0.04]))
    pred = model.predict(centre, points, pushes)
    truth = _law(push_actions(centre, pushes, points))
    moved = pred.centres[:, :2] - centre[:2]
    np.testing.assert_allclose(moved @ d[0, :2], truth[:, 0], atol=0.003)
    np.testing.assert_allclose(moved @ side[:2], truth[:, 1], atol=0.003)
    # the points turn with the predicted yaw about the predicted centre: a rigid motion
    spread = np.linalg.norm(points - centre, axis=1)
    np.testing.assert_allclose(np.linalg.norm(pred.points - pred.centres[:, None], axis=2),
                               np.tile(spread, (k, 1)), atol=1e-9)


def test_a_network_of_other_dims_or_a_missing_file_is_refused(tmp_path) -> None:
    with pytest.raises(ConfigError, match=r"dims \(3, 4\); got \(3, 3\)"):
        LearnedPush(MLPDynamics(3, 3, MLPConfig(), np.random.default_rng(0)))
    with pytest.raises(ConfigError, match="no push model at"):
        LearnedPush.from_file(tmp_path / "none.npz")


def test_a_drawer_is_pushed_with_the_heuristic_when_the_model_knows_only_blocks() -> None:
    from voxposer.control.pushing_loop import _model_for

    model = LearnedPush(MLPDynamics(3, 4, MLPConfig(), np.random.default_rng(0)))
    assert _model_for(model, sliding=True) is None  # a drawer: the heuristic
    assert _model_for(model, sliding=False) is model  # a block: the learned model
