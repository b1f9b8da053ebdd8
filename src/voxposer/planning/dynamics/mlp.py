"""A learned dynamics model: an MLP g_θ(o_t, a_t) → o_{t+1} (paper Sec. 3.4, Table 3).

Plain NumPy (see ``benchmarks/results/nn_library.txt`` for why not PyTorch): the inputs (o_t, a_t)
are normalised, the network predicts the normalised change Δ = o_{t+1} − o_t, and
:meth:`MLPDynamics.predict` returns o_t + Δ. The normaliser is fitted on transitions by
:func:`voxposer.planning.dynamics.training.train` (or :meth:`MLPDynamics.fit_normaliser`) and
saved with the weights.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError, DimensionMismatchError

_FORMAT = 1
_MIN_STD = 1e-8  # features with a smaller spread are left unscaled (constant in the data)


@dataclass(frozen=True)
class MLPConfig:
    """Network and optimiser parameters of :class:`MLPDynamics`.

    Attributes:
        hidden_sizes: width of each hidden ReLU layer (empty: a linear model).
        learning_rate: Adam step size (on normalised data).
        batch_size: transitions per minibatch.
        weight_decay: decoupled (AdamW) decay of the weight matrices per step, relative to the
            learning rate; biases are not decayed.
    """

    hidden_sizes: tuple[int, ...] = (128, 128)
    learning_rate: float = 1e-3
    batch_size: int = 256
    weight_decay: float = 0.0

    def __post_init__(self) -> None:
        sizes = self.hidden_sizes
        if not isinstance(sizes, tuple) or not all(
                isinstance(h, int) and not isinstance(h, bool) and h >= 1 for h in sizes):
            raise ConfigError(
                f"MLPConfig.hidden_sizes must be a tuple of ints >= 1; got {sizes!r}")
        if not np.isfinite(self.learning_rate) or self.learning_rate <= 0:
            raise ConfigError(
                f"MLPConfig.learning_rate must be finite and > 0; got {self.learning_rate!r}")
        if isinstance(self.batch_size, bool) or not isinstance(self.batch_size, int) \
                or self.batch_size < 1:
            raise ConfigError(f"MLPConfig.batch_size must be an int >= 1; got {self.batch_size!r}")
        if not np.isfinite(self.weight_decay) or self.weight_decay < 0:
            raise ConfigError(
                f"MLPConfig.weight_decay must be finite and >= 0; got {self.weight_decay!r}")


class Normaliser(NamedTuple):
    """Per-feature shift and scale of the network's inputs and target.

    Attributes:
        obs_mean, obs_std: of o_t, shape (D_o,).
        action_mean, action_std: of a_t, shape (D_a,).
        delta_mean, delta_std: of Δ = o_{t+1} − o_t, shape (D_o,).
    """

    obs_mean: NDArray[np.float64]
    obs_std: NDArray[np.float64]
    action_mean: NDArray[np.float64]
    action_std: NDArray[np.float64]
    delta_mean: NDArray[np.float64]
    delta_std: NDArray[np.float64]

    @classmethod
    def identity(cls, obs_dim: int, action_dim: int) -> Normaliser:
        """No shift, unit scale."""
        return cls(np.zeros(obs_dim), np.ones(obs_dim), np.zeros(action_dim),
                   np.ones(action_dim), np.zeros(obs_dim), np.ones(obs_dim))

    @classmethod
    def fit(cls, obs: NDArray[np.float64], actions: NDArray[np.float64],
            next_obs: NDArray[np.float64]) -> Normaliser:
        """Means and standard deviations of obs (N, D_o), actions (N, D_a) and next_obs − obs;
        a feature that is constant in the data keeps scale 1."""
        def spread(x: NDArray[np.float64]) -> NDArray[np.float64]:
            std = x.std(axis=0)
            return np.where(std > _MIN_STD, std, 1.0)
        delta = next_obs - obs
        return cls(obs.mean(axis=0), spread(obs), actions.mean(axis=0), spread(actions),
                   delta.mean(axis=0), spread(delta))


class MLPDynamics:
    """MLP dynamics model over normalised inputs predicting the change of observation.

    Args:
        obs_dim: D_o, the observation size.
        action_dim: D_a, the action size.
        config: network and optimiser parameters.
        rng: source of the initial weights (He-normal for ReLU layers, biases zero).

    Attributes:
        params: [W_0, b_0, W_1, b_1, …]; W_i has shape (in_i, out_i), b_i (out_i,); updated in
            place by the optimiser.
        normaliser: the current :class:`Normaliser` (identity until fitted).
        normaliser_fitted: whether ``normaliser`` was fitted on data.
    """

    def __init__(self, obs_dim: int, action_dim: int, config: MLPConfig,
                 rng: np.random.Generator) -> None:
        if obs_dim < 1 or action_dim < 1:
            raise ConfigError(f"MLPDynamics needs obs_dim >= 1 and action_dim >= 1; got "
                              f"{obs_dim!r}, {action_dim!r}")
        self.obs_dim = int(obs_dim)
        self.action_dim = int(action_dim)
        self.config = config
        sizes = [self.obs_dim + self.action_dim, *config.hidden_sizes, self.obs_dim]
        self.params: list[NDArray[np.float64]] = []
        for fan_in, fan_out in itertools.pairwise(sizes):
            self.params.append(rng.standard_normal((fan_in, fan_out)) * np.sqrt(2.0 / fan_in))
            self.params.append(np.zeros(fan_out))
        self.normaliser = Normaliser.identity(self.obs_dim, self.action_dim)
        self.normaliser_fitted = False

    def fit_normaliser(self, obs: NDArray[np.float64], actions: NDArray[np.float64],
                       next_obs: NDArray[np.float64]) -> None:
        """Fit the normaliser on transitions: obs (N, D_o), actions (N, D_a), next_obs (N, D_o)."""
        self._check(obs, actions, next_obs)
        self.normaliser = Normaliser.fit(obs, actions, next_obs)
        self.normaliser_fitted = True

    def predict(self, obs: NDArray[np.float64],
                actions: NDArray[np.float64]) -> NDArray[np.float64]:
        """Predicted next observations.

        Args:
            obs: observations, shape (S, D_o).
            actions: actions, shape (S, D_a).

        Returns:
            o_t + Δ̂, shape (S, D_o).

        Raises:
            DimensionMismatchError: the shapes do not match the model's dims.
        """
        obs, actions = self._check(obs, actions)
        n = self.normaliser
        out = self._forward(self._inputs(obs, actions))[-1]
        return obs + out * n.delta_std + n.delta_mean

    def loss(self, obs: NDArray[np.float64], actions: NDArray[np.float64],
             next_obs: NDArray[np.float64]) -> float:
        """Mean squared error of the normalised change: obs (B, D_o), actions (B, D_a),
        next_obs (B, D_o)."""
        obs, actions, next_obs = self._check(obs, actions, next_obs)
        n = self.normaliser
        residual = self._forward(self._inputs(obs, actions))[-1] - (
            next_obs - obs - n.delta_mean) / n.delta_std
        return float(np.mean(residual * residual))

    def loss_and_gradients(
        self, obs: NDArray[np.float64], actions: NDArray[np.float64],
        next_obs: NDArray[np.float64],
    ) -> tuple[float, list[NDArray[np.float64]]]:
        """Mean squared error of the normalised change on a minibatch, and its gradient.

        Args:
            obs: shape (B, D_o); actions: shape (B, D_a); next_obs: shape (B, D_o).

        Returns:
            the loss (mean over the B × D_o entries) and one gradient per entry of ``params``,
            each of that entry's shape.
        """
        obs, actions, next_obs = self._check(obs, actions, next_obs)
        n = self.normaliser
        target = (next_obs - obs - n.delta_mean) / n.delta_std
        acts = self._forward(self._inputs(obs, actions))
        residual = acts[-1] - target
        loss = float(np.mean(residual * residual))
        g = 2.0 * residual / residual.size  # dL/d(output), shape (B, D_o)
        grads: list[NDArray[np.float64]] = [np.empty(0)] * len(self.params)
        for i in reversed(range(len(self.params) // 2)):
            grads[2 * i] = acts[i].T @ g
            grads[2 * i + 1] = g.sum(axis=0)
            if i > 0:
                g = (g @ self.params[2 * i].T) * (acts[i] > 0)
        return loss, grads

    def save(self, path: str | Path) -> None:
        """Write the config, dims, normaliser and weights to an ``.npz`` file."""
        arrays: dict[str, NDArray] = {
            "format": np.array(_FORMAT),
            "config": np.array(json.dumps(dataclasses.asdict(self.config))),
            "dims": np.array([self.obs_dim, self.action_dim]),
            "normaliser_fitted": np.array(self.normaliser_fitted),
        }
        arrays |= {f"norm_{k}": v for k, v in self.normaliser._asdict().items()}
        arrays |= {f"param_{i}": p for i, p in enumerate(self.params)}
        np.savez(Path(path), **arrays)  # type: ignore[arg-type]

    def load(self, path: str | Path) -> None:
        """Replace this model's config, normaliser and weights by those saved in ``path``.

        Raises:
            DimensionMismatchError: the file holds a model of other (D_o, D_a).
            ConfigError: the file is not a saved :class:`MLPDynamics`.
        """
        with np.load(Path(path), allow_pickle=False) as f:
            try:
                dims = tuple(int(d) for d in f["dims"])
                config = json.loads(str(f["config"]))
                normaliser = Normaliser(**{k: f[f"norm_{k}"] for k in Normaliser._fields})
                fitted = bool(f["normaliser_fitted"])
                params = [f[f"param_{i}"] for i in range(2 * (len(config["hidden_sizes"]) + 1))]
            except KeyError as exc:
                raise ConfigError(f"{path} is not a saved MLPDynamics: {exc}") from exc
        if dims != (self.obs_dim, self.action_dim):
            raise DimensionMismatchError(
                f"{path} holds a model of (D_o, D_a) = {dims}, input ({sum(dims)},) → output "
                f"({dims[0]},); this model has (D_o, D_a) = {(self.obs_dim, self.action_dim)}, "
                f"input ({self.obs_dim + self.action_dim},) → output ({self.obs_dim},)")
        config["hidden_sizes"] = tuple(config["hidden_sizes"])
        self.config = MLPConfig(**config)
        self.params = [np.array(p, dtype=np.float64) for p in params]
        self.normaliser = Normaliser(*(np.array(v, dtype=np.float64) for v in normaliser))
        self.normaliser_fitted = fitted

    @classmethod
    def from_file(cls, path: str | Path) -> MLPDynamics:
        """A model as saved by :meth:`save` (its dims read from the file)."""
        with np.load(Path(path), allow_pickle=False) as f:
            if "dims" not in f:
                raise ConfigError(f"{path} is not a saved MLPDynamics: no 'dims'")
            obs_dim, action_dim = (int(d) for d in f["dims"])
        model = cls(obs_dim, action_dim, MLPConfig(hidden_sizes=()), np.random.default_rng(0))
        model.load(path)
        return model

    def _inputs(self, obs: NDArray[np.float64],
                actions: NDArray[np.float64]) -> NDArray[np.float64]:
        """Normalised network input, shape (S, D_o + D_a)."""
        n = self.normaliser
        return np.concatenate([(obs - n.obs_mean) / n.obs_std,
                               (actions - n.action_mean) / n.action_std], axis=1)

    def _forward(self, x: NDArray[np.float64]) -> list[NDArray[np.float64]]:
        """Every layer's output (ReLU after all but the last), starting with the input x."""
        acts = [x]
        last = len(self.params) // 2 - 1
        for i in range(last + 1):
            z = acts[-1] @ self.params[2 * i] + self.params[2 * i + 1]
            acts.append(z if i == last else np.maximum(z, 0.0))
        return acts

    def _check(self, obs: NDArray, actions: NDArray,
               next_obs: NDArray | None = None) -> tuple[NDArray[np.float64], ...]:
        """The arrays as float64, after checking shapes (S, D_o), (S, D_a)[, (S, D_o)]."""
        arrays = [np.asarray(obs, dtype=np.float64), np.asarray(actions, dtype=np.float64)]
        expect = [(self.obs_dim,), (self.action_dim,)]
        if next_obs is not None:
            arrays.append(np.asarray(next_obs, dtype=np.float64))
            expect.append((self.obs_dim,))
        s = arrays[0].shape[0] if arrays[0].ndim == 2 else -1
        if any(a.ndim != 2 or a.shape != (s, *e) for a, e in zip(arrays, expect, strict=True)):
            want = ", ".join(f"(S, {e[0]})" for e in expect)
            got = ", ".join(str(a.shape) for a in arrays)
            raise DimensionMismatchError(
                f"MLPDynamics with (D_o, D_a) = {(self.obs_dim, self.action_dim)} expects shapes "
                f"{want}; got {got}")
        return tuple(arrays)
