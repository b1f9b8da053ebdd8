from pathlib import Path

import numpy as np
import pytest

from voxposer.errors import DimensionMismatchError, DivergedError, InvalidActionError
from voxposer.planning.dynamics import (
    LinearDynamics,
    MLPConfig,
    MLPDynamics,
    Transitions,
    train,
)

D_O, D_A = 4, 2
RNG = np.random.default_rng(42)
A = np.eye(D_O) + 0.1 * RNG.normal(size=(D_O, D_O))
B = 0.2 * RNG.normal(size=(D_O, D_A))
SYSTEM = LinearDynamics(A, B)


def _linear_data(n: int, seed: int) -> Transitions:
    rng = np.random.default_rng(seed)
    obs, act = rng.uniform(-1, 1, (n, D_O)), rng.uniform(-1, 1, (n, D_A))
    return Transitions(obs, act, SYSTEM.predict(obs, act))


def _model(**kw: object) -> MLPDynamics:
    cfg = MLPConfig(**{"hidden_sizes": (64, 64), "learning_rate": 3e-3, **kw})  # type: ignore[arg-type]
    return MLPDynamics(D_O, D_A, cfg, np.random.default_rng(1))


def test_learns_a_linear_system_to_a_small_held_out_error() -> None:
    """x' = Ax + Bu (states and actions in [-1, 1]): 320 Adam steps (10 epochs × 32 minibatches
    of 64) bring the held-out RMSE of the next state below 15 % of the spread of its change
    (≈ 0.02 in state units; measured ≈ 7 %), where predicting "no change" errs by ≈ 100 %."""
    train_set, held_out = _linear_data(2500, 0).split(0.2, np.random.default_rng(0))
    model = _model(learning_rate=1e-2, batch_size=64)
    report = train(model, train_set, np.random.default_rng(2), 10, held_out=held_out)
    assert report.steps == 320
    spread = (held_out.next_obs - held_out.obs).std(axis=0)
    assert report.held_out_rmse.shape == (D_O,)
    assert (report.held_out_rmse < 0.15 * spread).all(), report.held_out_rmse / spread
    fresh = _linear_data(200, 7)  # and on states it never saw
    error = model.predict(fresh.obs, fresh.actions) - fresh.next_obs
    assert (np.sqrt((error ** 2).mean(axis=0)) < 0.15 * spread).all()


def test_loss_decreases() -> None:
    report = train(_model(), _linear_data(1000, 1), np.random.default_rng(0), 15,
                   held_out=_linear_data(200, 2))
    assert report.losses.shape == (15,) and report.held_out_losses.shape == (15,)
    assert report.losses[-1] < 0.1 * report.losses[0]
    assert report.held_out_losses[-1] < 0.1 * report.held_out_losses[0]
    assert (np.diff(report.losses[:5]) < 0).all()


def test_same_seeds_train_the_same_model() -> None:
    data = _linear_data(300, 3)
    a, b = _model(), _model()
    train(a, data, np.random.default_rng(5), 3)
    train(b, data, np.random.default_rng(5), 3)
    np.testing.assert_array_equal(a.predict(data.obs, data.actions),
                                  b.predict(data.obs, data.actions))


def test_normaliser_is_fitted_once_unless_asked() -> None:
    model = _model()
    train(model, _linear_data(300, 3), np.random.default_rng(0), 1)
    first = model.normaliser
    shifted = _linear_data(300, 4)
    shifted = Transitions(shifted.obs + 5, shifted.actions, shifted.next_obs + 5)
    train(model, shifted, np.random.default_rng(0), 1)
    assert model.normaliser is first
    train(model, shifted, np.random.default_rng(0), 1, fit_normaliser=True)
    assert model.normaliser.obs_mean == pytest.approx(first.obs_mean + 5, abs=0.2)


def test_a_huge_learning_rate_diverges_naming_the_epoch() -> None:
    with pytest.raises(DivergedError, match=r"epoch \d+") as info:
        train(_model(learning_rate=1e200), _linear_data(600, 5), np.random.default_rng(0), 5)
    assert 0 <= info.value.epoch < 5
    assert not np.isfinite(info.value.loss)


def test_nan_weights_diverge_in_the_first_epoch() -> None:
    model = _model()
    model.params[0][0, 0] = np.nan
    with pytest.raises(DivergedError, match="epoch 0"):
        train(model, _linear_data(100, 5), np.random.default_rng(0), 3)


def test_transitions_of_other_dims_are_refused() -> None:
    other = Transitions(np.zeros((5, 3)), np.zeros((5, D_A)), np.zeros((5, 3)))
    with pytest.raises(DimensionMismatchError, match=r"\(3, 2\).*\(4, 2\)"):
        train(_model(), other, np.random.default_rng(0), 1)
    with pytest.raises(DimensionMismatchError):
        _linear_data(3, 0).concat(other)


def test_transitions_validate_concatenate_split_and_round_trip(tmp_path: Path) -> None:
    with pytest.raises(DimensionMismatchError):
        Transitions(np.zeros((5, D_O)), np.zeros((4, D_A)), np.zeros((5, D_O)))
    with pytest.raises(InvalidActionError, match=r"actions\[2\]"):
        Transitions(np.zeros((5, D_O)), np.where(np.arange(5)[:, None] == 2, np.inf, 0.0)
                    * np.ones((5, D_A)), np.zeros((5, D_O)))
    a, b = _linear_data(10, 0), _linear_data(6, 1)
    both = a.concat(b, Transitions.empty(D_O, D_A))
    assert len(both) == 16 and both.dims == (D_O, D_A)
    np.testing.assert_array_equal(both.actions[10:], b.actions)
    train_set, held = both.split(0.25, np.random.default_rng(0))
    assert (len(train_set), len(held)) == (12, 4)
    assert sorted(map(tuple, np.vstack([train_set.obs, held.obs]))) == sorted(map(tuple, both.obs))
    both.save(tmp_path / "t.npz")
    loaded = Transitions.load(tmp_path / "t.npz")
    for k in ("obs", "actions", "next_obs"):
        np.testing.assert_array_equal(getattr(loaded, k), getattr(both, k))


def test_transitions_from_a_rollout_are_copies() -> None:
    obs = np.arange(12.0).reshape(4, 3)
    t = Transitions.from_rollout(obs, np.ones((3, 1)))
    obs[0] = -1
    np.testing.assert_array_equal(t.obs[0], [0, 1, 2])
    np.testing.assert_array_equal(t.next_obs[-1], [9, 10, 11])
    assert not t.obs.flags.writeable
