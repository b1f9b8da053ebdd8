import re
from pathlib import Path

import numpy as np
import pytest

from voxposer.errors import ConfigError, DimensionMismatchError
from voxposer.planning.dynamics import MLPConfig, MLPDynamics, StateDynamicsModel, Transitions

D_O, D_A = 4, 2


def _model(seed: int = 0, hidden: tuple[int, ...] = (16, 8), **kw: float) -> MLPDynamics:
    return MLPDynamics(D_O, D_A, MLPConfig(hidden_sizes=hidden, **kw),  # type: ignore[arg-type]
                       np.random.default_rng(seed))


def _data(n: int, seed: int = 0) -> Transitions:
    rng = np.random.default_rng(seed)
    obs, act = rng.normal(size=(n, D_O)), rng.normal(size=(n, D_A))
    return Transitions(obs, act, obs + np.tanh(obs[:, ::-1] + act.sum(1, keepdims=True)))


def test_is_a_state_dynamics_model_with_batched_shapes() -> None:
    model = _model()
    assert isinstance(model, StateDynamicsModel)
    data = _data(7)
    out = model.predict(data.obs, data.actions)
    assert out.shape == (7, D_O)
    rows = np.stack([model.predict(data.obs[i:i + 1], data.actions[i:i + 1])[0] for i in range(7)])
    np.testing.assert_allclose(out, rows, rtol=1e-12, atol=1e-12)


def test_predicts_the_change_of_observation() -> None:
    """With a zero output layer the prediction is o_t + delta_mean (in observation units)."""
    model = _model()
    data = _data(50)
    model.fit_normaliser(data.obs, data.actions, data.next_obs)
    model.params[-2][:] = 0.0
    model.params[-1][:] = 0.0
    pred = model.predict(data.obs, data.actions)
    np.testing.assert_allclose(pred, data.obs + (data.next_obs - data.obs).mean(axis=0))


def test_gradients_match_finite_differences() -> None:
    model = _model(seed=3, hidden=(5, 4))
    data = _data(9, seed=1)
    model.fit_normaliser(data.obs, data.actions, data.next_obs)
    loss, grads = model.loss_and_gradients(data.obs, data.actions, data.next_obs)
    assert loss == pytest.approx(model.loss(data.obs, data.actions, data.next_obs))
    rng = np.random.default_rng(0)
    for p, g in zip(model.params, grads, strict=True):
        assert g.shape == p.shape
        for flat in rng.choice(p.size, size=min(p.size, 5), replace=False):
            idx = np.unravel_index(flat, p.shape)
            old = p[idx]
            p[idx] = old + 1e-6
            up = model.loss(data.obs, data.actions, data.next_obs)
            p[idx] = old - 1e-6
            down = model.loss(data.obs, data.actions, data.next_obs)
            p[idx] = old
            assert g[idx] == pytest.approx((up - down) / 2e-6, rel=1e-4, abs=1e-8)


def test_same_generator_seed_gives_same_weights() -> None:
    a, b, c = _model(5), _model(5), _model(6)
    assert all(np.array_equal(x, y) for x, y in zip(a.params, b.params, strict=True))
    assert not np.array_equal(a.params[0], c.params[0])


def test_save_load_round_trip_gives_identical_predictions(tmp_path: Path) -> None:
    model = _model(hidden=(12, 6, 5), learning_rate=3e-3, weight_decay=1e-4)
    data = _data(30)
    model.fit_normaliser(data.obs, data.actions, data.next_obs)
    model.save(tmp_path / "m.npz")
    other = _model(seed=9)  # other weights and hidden sizes, same dims
    other.load(tmp_path / "m.npz")
    fresh = MLPDynamics.from_file(tmp_path / "m.npz")
    for loaded in (other, fresh):
        assert loaded.config == model.config
        assert loaded.normaliser_fitted
        np.testing.assert_array_equal(loaded.predict(data.obs, data.actions),
                                      model.predict(data.obs, data.actions))


def test_loading_other_dims_is_refused_naming_both_shapes(tmp_path: Path) -> None:
    MLPDynamics(5, 3, MLPConfig(), np.random.default_rng(0)).save(tmp_path / "m.npz")
    model = _model()
    before = [p.copy() for p in model.params]
    with pytest.raises(DimensionMismatchError, match=r"\(5, 3\).*\(4, 2\)"):
        model.load(tmp_path / "m.npz")
    assert all(np.array_equal(p, q) for p, q in zip(model.params, before, strict=True))


def test_a_file_that_is_not_a_model_is_refused(tmp_path: Path) -> None:
    np.savez(tmp_path / "x.npz", dims=np.array([D_O, D_A]))
    with pytest.raises(ConfigError, match="not a saved MLPDynamics"):
        _model().load(tmp_path / "x.npz")


def test_predict_refuses_other_shapes() -> None:
    model = _model()
    with pytest.raises(DimensionMismatchError, match=r"\(3, 5\)"):
        model.predict(np.zeros((3, 5)), np.zeros((3, D_A)))
    with pytest.raises(DimensionMismatchError):
        model.predict(np.zeros((3, D_O)), np.zeros((2, D_A)))


@pytest.mark.parametrize(("field", "value"), [
    ("hidden_sizes", (64, 0)), ("hidden_sizes", [64]), ("learning_rate", 0.0),
    ("learning_rate", float("nan")), ("batch_size", 0), ("batch_size", 2.5),
    ("weight_decay", -1e-3),
])
def test_bad_configs_raise_naming_the_field_and_value(field: str, value: object) -> None:
    with pytest.raises(ConfigError, match=rf"MLPConfig\.{field}.*{re.escape(repr(value))}"):
        MLPConfig(**{field: value})  # type: ignore[arg-type]
