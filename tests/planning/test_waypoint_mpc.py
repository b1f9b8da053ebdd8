import itertools
import re

import numpy as np
import pytest
from numpy.typing import NDArray

from voxposer.errors import ConfigError, InvalidActionError, PlanningError
from voxposer.planning.dynamics import LinearDynamics, MLPConfig, MLPDynamics, Transitions, train
from voxposer.planning.waypoint_mpc import (
    WaypointMPCConfig,
    plan_action,
    rollout,
    sample_action_sequences,
)

DT = 0.1
#: a point mass on a line per axis: o = (position [m] (2), velocity [m/s] (2)), a = acceleration
DOUBLE_INTEGRATOR = LinearDynamics(
    np.block([[np.eye(2), DT * np.eye(2)], [np.zeros((2, 2)), np.eye(2)]]),
    np.vstack([0.5 * DT ** 2 * np.eye(2), DT * np.eye(2)]))
GOAL = np.array([0.3, -0.2])


def _cfg(d: int = 2, **kw: object) -> WaypointMPCConfig:
    return WaypointMPCConfig(action_low=(-1.0,) * d, action_high=(1.0,) * d, **kw)  # type: ignore[arg-type]


def _reach_cost(pred: NDArray[np.float64], actions: NDArray[np.float64]) -> NDArray[np.float64]:
    """Squared distance of the positions to GOAL plus some of the speed, summed over H: (N,)."""
    return (((pred[..., :2] - GOAL) ** 2).sum(-1) + 0.05 * (pred[..., 2:] ** 2).sum(-1)).sum(-1)


def _distance(obs: NDArray[np.float64]) -> float:
    return float(np.linalg.norm(obs[:2] - GOAL))


def test_perfect_model_drives_the_state_to_the_goal() -> None:
    cfg = _cfg(n_samples=1000, horizon=10)
    rng, obs = np.random.default_rng(0), np.zeros(4)
    distances, costs = [_distance(obs)], []
    for _ in range(40):
        plan = plan_action(DOUBLE_INTEGRATOR, obs, _reach_cost, rng, cfg)
        obs = DOUBLE_INTEGRATOR.predict(obs[None], plan.action[None])[0]
        np.testing.assert_allclose(plan.predicted_next_obs, obs)  # the model is the world
        distances.append(_distance(obs))
        costs.append(plan.cost)
    assert max(distances[-10:]) < 0.03, distances[-10:]  # it stays there
    assert np.linalg.norm(obs[2:]) < 0.15  # accelerations are sampled in [-1, 1] m/s²
    assert costs[-1] < 0.02 * costs[0]
    assert all(b < a for a, b in itertools.pairwise(costs[:11]))  # while it approaches


def test_a_learned_model_drives_the_state_towards_the_goal() -> None:
    """The chain of paper Table 3: transitions → MLP → MPC through the MLP."""
    rng = np.random.default_rng(1)
    obs, act = rng.uniform(-1, 1, (3000, 4)), rng.uniform(-1, 1, (3000, 2))
    model = MLPDynamics(4, 2, MLPConfig(hidden_sizes=(64, 64), learning_rate=1e-2,
                                        batch_size=128), np.random.default_rng(2))
    train(model, Transitions(obs, act, DOUBLE_INTEGRATOR.predict(obs, act)), rng, 8)
    state, cfg = np.zeros(4), _cfg(n_samples=500, horizon=8)
    for _ in range(25):
        plan = plan_action(model, state, _reach_cost, rng, cfg)
        state = DOUBLE_INTEGRATOR.predict(state[None], plan.action[None])[0]
    assert _distance(state) < 0.2 * _distance(np.zeros(4))


def test_samples_with_a_prior_stay_near_the_prior() -> None:
    prior = np.array([[0.2, -0.1], [0.3, 0.0], [0.4, 0.1]])
    cfg = _cfg(n_samples=20_000, horizon=3, sigma=(0.05, 0.1))
    samples = sample_action_sequences(np.random.default_rng(0), cfg, prior)
    assert samples.shape == (20_000, 3, 2)
    np.testing.assert_allclose(samples.mean(axis=0), prior, atol=0.005)
    np.testing.assert_allclose(samples.std(axis=0), np.tile([0.05, 0.1], (3, 1)), rtol=0.05)


def test_a_short_prior_is_padded_with_its_last_action_and_samples_are_clipped() -> None:
    cfg = _cfg(n_samples=5000, horizon=4, sigma=0.2)
    samples = sample_action_sequences(np.random.default_rng(0), cfg, np.array([[0.0, 0.95]]))
    assert samples.shape == (5000, 4, 2)
    assert samples.max() <= 1.0 and samples.min() >= -1.0
    assert (samples[..., 1] == 1.0).mean() > 0.3  # N(0.95, 0.2²) beyond 1 is clipped
    np.testing.assert_allclose(samples[..., 0].mean(axis=0), 0.0, atol=0.02)


def test_samples_without_a_prior_stay_within_and_cover_the_bounds() -> None:
    cfg = WaypointMPCConfig(action_low=(-0.05, 0.0, 2.0), action_high=(0.05, 1.0, 3.0),
                            n_samples=2000, horizon=5)
    samples = sample_action_sequences(np.random.default_rng(0), cfg)
    assert samples.shape == (2000, 5, 3)
    flat = samples.reshape(-1, 3)
    lo, hi = np.array(cfg.action_low), np.array(cfg.action_high)
    assert (flat >= lo).all() and (flat <= hi).all()
    for d in range(3):  # every tenth of each dim's range gets close to a tenth of the samples
        counts, _ = np.histogram(flat[:, d], bins=10, range=(lo[d], hi[d]))
        assert counts.min() > 0.08 * len(flat), counts


def test_same_generator_seed_gives_the_same_action() -> None:
    cfg = _cfg(n_samples=200, horizon=4)
    obs = np.array([0.1, 0.0, 0.0, 0.0])
    a = plan_action(DOUBLE_INTEGRATOR, obs, _reach_cost, np.random.default_rng(7), cfg)
    b = plan_action(DOUBLE_INTEGRATOR, obs, _reach_cost, np.random.default_rng(7), cfg)
    c = plan_action(DOUBLE_INTEGRATOR, obs, _reach_cost, np.random.default_rng(8), cfg)
    np.testing.assert_array_equal(a.action, b.action)
    np.testing.assert_array_equal(a.sequence, b.sequence)
    assert not np.array_equal(a.action, c.action)


def test_the_plan_is_the_best_sampled_sequence_and_read_only() -> None:
    cfg = _cfg(n_samples=300, horizon=4)
    obs = np.array([0.0, 0.1, 0.2, 0.0])
    plan = plan_action(DOUBLE_INTEGRATOR, obs, _reach_cost, np.random.default_rng(3), cfg)
    samples = sample_action_sequences(np.random.default_rng(3), cfg)
    predicted = rollout(DOUBLE_INTEGRATOR, obs, samples)
    costs = _reach_cost(predicted, samples)
    assert plan.cost == pytest.approx(costs.min())
    np.testing.assert_array_equal(plan.sequence, samples[np.argmin(costs)])
    np.testing.assert_array_equal(plan.action, plan.sequence[0])
    assert plan.predicted_obs.shape == (4, 4)
    with pytest.raises(ValueError, match="read-only"):
        plan.action[0] = 5.0


def test_rollout_is_batched_over_samples() -> None:
    actions = np.random.default_rng(0).uniform(-1, 1, (6, 3, 2))
    obs = np.array([0.1, 0.2, 0.3, 0.4])
    out = rollout(DOUBLE_INTEGRATOR, obs, actions)
    for i in range(6):
        o = obs
        for h in range(3):
            o = DOUBLE_INTEGRATOR.a @ o + DOUBLE_INTEGRATOR.b @ actions[i, h]
            np.testing.assert_allclose(out[i, h], o)


def test_non_finite_costs_are_skipped_and_bad_cost_shapes_refused() -> None:
    cfg = _cfg(n_samples=100, horizon=2)
    obs = np.zeros(4)

    def half_nan(pred: NDArray[np.float64], actions: NDArray[np.float64]) -> NDArray[np.float64]:
        c = _reach_cost(pred, actions)
        c[::2] = np.nan
        return c

    plan = plan_action(DOUBLE_INTEGRATOR, obs, half_nan, np.random.default_rng(0), cfg)
    assert np.isfinite(plan.cost)
    with pytest.raises(PlanningError, match="no sampled action sequence"):
        plan_action(DOUBLE_INTEGRATOR, obs, lambda p, a: np.full(100, np.inf),
                    np.random.default_rng(0), cfg)
    with pytest.raises(PlanningError, match=re.escape("(100,); got (100, 2)")):
        plan_action(DOUBLE_INTEGRATOR, obs, lambda p, a: p.sum(-1),
                    np.random.default_rng(0), cfg)


def test_a_malformed_prior_or_observation_is_refused() -> None:
    cfg = _cfg()
    with pytest.raises(InvalidActionError, match=r"\(H', 2\).*\(3, 3\)"):
        plan_action(DOUBLE_INTEGRATOR, np.zeros(4), _reach_cost, np.random.default_rng(0), cfg,
                    prior=np.zeros((3, 3)))
    with pytest.raises(InvalidActionError, match="finite"):
        plan_action(DOUBLE_INTEGRATOR, np.full(4, np.nan), _reach_cost,
                    np.random.default_rng(0), cfg)


@pytest.mark.parametrize(("kw", "field"), [
    ({"action_low": (0.0, 1.0), "action_high": (1.0, 1.0)}, "action_low"),
    ({"action_low": (0.0,), "action_high": (1.0, 1.0)}, "action_low"),
    ({"n_samples": 0}, "n_samples"),
    ({"horizon": 0}, "horizon"),
    ({"sigma": -0.1}, "sigma"),
    ({"sigma": (0.1, 0.1, 0.1)}, "sigma"),
])
def test_bad_configs_raise_naming_the_field(kw: dict[str, object], field: str) -> None:
    args: dict[str, object] = {"action_low": (-1.0, -1.0), "action_high": (1.0, 1.0), **kw}
    with pytest.raises(ConfigError, match=rf"WaypointMPCConfig\.{field}"):
        WaypointMPCConfig(**args)  # type: ignore[arg-type]
