"""Training a learned dynamics model on collected transitions (paper Sec. 3.4).

The robot alternates between collecting transitions (o_t, a_t, o_{t+1}) with the MPC and fitting
g_θ by minimising the L2 error between predicted and observed next observations; this module
holds the transitions (:class:`Transitions`) and the fitting (:func:`train`, minibatch Adam).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import (
    ConfigError,
    DimensionMismatchError,
    DivergedError,
    InvalidActionError,
)
from voxposer.planning.dynamics.mlp import MLPDynamics


@dataclass(frozen=True)
class Transitions:
    """N transitions (o_t, a_t, o_{t+1}); the arrays are copied and made read-only.

    Attributes:
        obs: o_t, shape (N, D_o).
        actions: a_t, shape (N, D_a).
        next_obs: o_{t+1}, shape (N, D_o).

    Raises:
        DimensionMismatchError: the shapes do not fit together.
        InvalidActionError: an entry is NaN/inf.
    """

    obs: NDArray[np.float64]
    actions: NDArray[np.float64]
    next_obs: NDArray[np.float64]

    def __post_init__(self) -> None:
        arrays = {}
        for name in ("obs", "actions", "next_obs"):
            a = np.array(getattr(self, name), dtype=np.float64)
            a.flags.writeable = False
            arrays[name] = a
            object.__setattr__(self, name, a)
        o, a, o2 = arrays["obs"], arrays["actions"], arrays["next_obs"]
        if o.ndim != 2 or a.ndim != 2 or o2.shape != o.shape or len(a) != len(o):
            raise DimensionMismatchError(
                f"Transitions needs obs (N, D_o), actions (N, D_a), next_obs (N, D_o); got "
                f"{o.shape}, {a.shape}, {o2.shape}")
        for name, x in arrays.items():
            if not np.isfinite(x).all():
                bad = int(np.argwhere(~np.isfinite(x))[0, 0])
                raise InvalidActionError(f"Transitions.{name}[{bad}] is not finite: {x[bad]}")

    def __len__(self) -> int:
        return len(self.obs)

    @property
    def dims(self) -> tuple[int, int]:
        """(D_o, D_a)."""
        return self.obs.shape[1], self.actions.shape[1]

    @classmethod
    def empty(cls, obs_dim: int, action_dim: int) -> Transitions:
        """No transitions, of the given dims."""
        return cls(np.zeros((0, obs_dim)), np.zeros((0, action_dim)), np.zeros((0, obs_dim)))

    @classmethod
    def from_rollout(cls, obs: NDArray[np.float64], actions: NDArray[np.float64]) -> Transitions:
        """The T transitions of one rollout: obs (T + 1, D_o) visited, actions (T, D_a) taken."""
        obs = np.asarray(obs, dtype=np.float64)
        return cls(obs[:-1], actions, obs[1:])

    def concat(self, *others: Transitions) -> Transitions:
        """These transitions followed by ``others`` (all of the same dims)."""
        for other in others:
            if other.dims != self.dims:
                raise DimensionMismatchError(
                    f"cannot concatenate transitions of (D_o, D_a) = {other.dims} to "
                    f"{self.dims}")
        every = (self, *others)
        return Transitions(*(np.concatenate([getattr(t, k) for t in every])
                             for k in ("obs", "actions", "next_obs")))

    def subset(self, index: NDArray[np.intp] | slice) -> Transitions:
        """The transitions at ``index``."""
        return Transitions(self.obs[index], self.actions[index], self.next_obs[index])

    def split(self, held_out: float, rng: np.random.Generator) -> tuple[Transitions, Transitions]:
        """A random (training, held-out) split; ``held_out`` is the held-out fraction in (0, 1)."""
        if not 0 < held_out < 1:
            raise ConfigError(f"Transitions.split held_out must be in (0, 1); got {held_out!r}")
        order = rng.permutation(len(self))
        k = round(held_out * len(self))
        return self.subset(order[k:]), self.subset(order[:k])

    def save(self, path: str | Path) -> None:
        """Write to an ``.npz`` file."""
        np.savez(Path(path), obs=self.obs, actions=self.actions, next_obs=self.next_obs)

    @classmethod
    def load(cls, path: str | Path) -> Transitions:
        """Read what :meth:`save` wrote."""
        with np.load(Path(path), allow_pickle=False) as f:
            return cls(f["obs"], f["actions"], f["next_obs"])


class TrainReport(NamedTuple):
    """What :func:`train` did.

    Attributes:
        losses: mean minibatch loss of each epoch (MSE of the normalised change), shape (E,).
        held_out_losses: the same loss on the held-out transitions after each epoch, shape (E,)
            (empty without held-out transitions).
        held_out_rmse: root-mean-square error of the predicted next observation on the held-out
            transitions after the last epoch, per observation dim, in its units, shape (D_o,)
            (empty without held-out transitions).
        steps: optimiser steps taken.
    """

    losses: NDArray[np.float64]
    held_out_losses: NDArray[np.float64]
    held_out_rmse: NDArray[np.float64]
    steps: int


class Adam:
    """Adam with decoupled weight decay (AdamW) over a list of arrays updated in place.

    Args:
        params: the arrays to update (e.g. :attr:`MLPDynamics.params`).
        learning_rate: step size.
        weight_decay: decay of the 2-D arrays (weight matrices) per step, × learning_rate.
        betas: decay rates of the first and second moment estimates.
        eps: added to the second moment's root (numerical safety).
    """

    def __init__(self, params: list[NDArray[np.float64]], learning_rate: float,
                 weight_decay: float = 0.0, betas: tuple[float, float] = (0.9, 0.999),
                 eps: float = 1e-8) -> None:
        self.params = params
        self.learning_rate = learning_rate
        self.weight_decay = weight_decay
        self.betas = betas
        self.eps = eps
        self.m = [np.zeros_like(p) for p in params]
        self.v = [np.zeros_like(p) for p in params]
        self.t = 0

    def step(self, grads: list[NDArray[np.float64]]) -> None:
        """One update from one gradient per parameter (same shapes)."""
        self.t += 1
        b1, b2 = self.betas
        scale = self.learning_rate * np.sqrt(1 - b2 ** self.t) / (1 - b1 ** self.t)
        for p, g, m, v in zip(self.params, grads, self.m, self.v, strict=True):
            m *= b1
            m += (1 - b1) * g
            v *= b2
            v += (1 - b2) * g * g
            if self.weight_decay and p.ndim == 2:
                p *= 1 - self.learning_rate * self.weight_decay
            p -= scale * m / (np.sqrt(v) + self.eps)


def train(model: MLPDynamics, transitions: Transitions, rng: np.random.Generator,
          epochs: int, *, held_out: Transitions | None = None,
          fit_normaliser: bool | None = None) -> TrainReport:
    """Fit ``model`` to ``transitions`` by minibatch Adam on the L2 loss (in place).

    Each epoch visits every transition once in a random order, in minibatches of
    ``model.config.batch_size`` (the last one smaller), with a fresh optimiser per call.

    Args:
        model: the model to train, updated in place.
        transitions: training transitions of the model's dims, N >= 1.
        rng: source of the minibatch order.
        epochs: passes over the transitions, >= 1.
        held_out: if given, transitions the loss and RMSE are also reported on.
        fit_normaliser: refit the model's normaliser on ``transitions`` first; by default only
            if it was never fitted (refitting changes what the weights mean: do it early, while
            the data set still grows a lot).

    Raises:
        DimensionMismatchError: the transitions have other dims than the model.
        DivergedError: a minibatch loss became NaN/inf (names the epoch).
    """
    if epochs < 1 or len(transitions) == 0:
        raise ConfigError(f"train needs epochs >= 1 and transitions; got {epochs!r} epochs, "
                         f"{len(transitions)} transitions")
    for t in (transitions, held_out):
        if t is not None and t.dims != (model.obs_dim, model.action_dim):
            raise DimensionMismatchError(
                f"transitions of (D_o, D_a) = {t.dims} cannot train a model of "
                f"{(model.obs_dim, model.action_dim)}")
    if fit_normaliser or (fit_normaliser is None and not model.normaliser_fitted):
        model.fit_normaliser(transitions.obs, transitions.actions, transitions.next_obs)
    cfg = model.config
    opt = Adam(model.params, cfg.learning_rate, cfg.weight_decay)
    n, bs = len(transitions), cfg.batch_size
    losses, held_losses = np.zeros(epochs), []
    o, a, o2 = transitions.obs, transitions.actions, transitions.next_obs
    with np.errstate(over="ignore", invalid="ignore"):  # divergence is detected below
        for epoch in range(epochs):
            order = rng.permutation(n)
            total = 0.0
            for start in range(0, n, bs):
                idx = order[start:start + bs]
                loss, grads = model.loss_and_gradients(o[idx], a[idx], o2[idx])
                if not np.isfinite(loss):
                    raise DivergedError(epoch, loss)
                opt.step(grads)
                total += loss * len(idx)
            losses[epoch] = total / n
            if not all(np.isfinite(p).all() for p in model.params):
                raise DivergedError(epoch, float("nan"))
            if held_out is not None and len(held_out):
                held_losses.append(model.loss(held_out.obs, held_out.actions, held_out.next_obs))
    rmse = np.zeros(0)
    if held_out is not None and len(held_out):
        error = model.predict(held_out.obs, held_out.actions) - held_out.next_obs
        rmse = np.sqrt(np.mean(error * error, axis=0))
    return TrainReport(losses, np.array(held_losses), rmse, opt.t)
