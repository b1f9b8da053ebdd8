"""Random-shooting MPC over a state dynamics model (paper Sec. 3.4 and 4.3, Table 3).

At every step the robot samples N action sequences of horizon H, rolls each out through a
:class:`~voxposer.planning.dynamics.StateDynamicsModel` (the learned MLP, a known model, the
simulator), scores the predicted observations with a cost function and executes the first action
of the best sequence. Actions are sampled either around a prior — the zero-shot trajectory τ₀
synthesised by VoxPoser, as end-effector displacements: a + ε, ε ~ N(0, σ²) ("with prior") — or
uniformly over the action bounds ("without prior"). Everything is batched over the N samples; the
only Python loop is over the H steps.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError, InvalidActionError, PlanningError
from voxposer.planning.dynamics.state_model import StateDynamicsModel

#: cost_fn(predicted_obs (N, H, D_o), actions (N, H, D_a)) -> costs (N,), lower is better.
CostFn = Callable[[NDArray[np.float64], NDArray[np.float64]], NDArray[np.float64]]


@dataclass(frozen=True)
class WaypointMPCConfig:
    """Random-shooting parameters; actions are in the units of the model's action space (e.g.
    an end-effector displacement [m] (3) and a gripper command).

    Attributes:
        action_low: lower action bound per dim, length D_a.
        action_high: upper action bound per dim, length D_a (> action_low).
        n_samples: N, action sequences sampled per step.
        horizon: H, steps each sequence is rolled out.
        sigma: standard deviation of the exploration noise around a prior, one value for all
            dims or one per dim (action units).
    """

    action_low: tuple[float, ...]
    action_high: tuple[float, ...]
    n_samples: int = 1000
    horizon: int = 5
    sigma: float | tuple[float, ...] = 0.01

    def __post_init__(self) -> None:
        lo = np.asarray(self.action_low, dtype=np.float64)
        hi = np.asarray(self.action_high, dtype=np.float64)
        if lo.ndim != 1 or len(lo) == 0 or lo.shape != hi.shape or not np.isfinite(lo).all() \
                or not np.isfinite(hi).all() or not (lo < hi).all():
            raise ConfigError(
                "WaypointMPCConfig.action_low/action_high must be finite, of the same length "
                f">= 1, with low < high; got {self.action_low!r}, {self.action_high!r}")
        object.__setattr__(self, "action_low", tuple(float(x) for x in lo))
        object.__setattr__(self, "action_high", tuple(float(x) for x in hi))
        if isinstance(self.n_samples, bool) or not isinstance(self.n_samples, int) \
                or self.n_samples < 1:
            raise ConfigError(
                f"WaypointMPCConfig.n_samples must be an int >= 1; got {self.n_samples!r}")
        if isinstance(self.horizon, bool) or not isinstance(self.horizon, int) \
                or self.horizon < 1:
            raise ConfigError(
                f"WaypointMPCConfig.horizon must be an int >= 1; got {self.horizon!r}")
        sigma = np.asarray(self.sigma, dtype=np.float64)
        if sigma.shape not in ((), lo.shape) or not np.isfinite(sigma).all() \
                or (sigma < 0).any():
            raise ConfigError(
                f"WaypointMPCConfig.sigma must be >= 0, one value or {len(lo)} (one per action "
                f"dim); got {self.sigma!r}")
        if sigma.ndim:
            object.__setattr__(self, "sigma", tuple(float(x) for x in sigma))

    @property
    def action_dim(self) -> int:
        """D_a."""
        return len(self.action_low)


class WaypointPlan(NamedTuple):
    """The MPC's choice at one step (arrays are copies, read-only).

    Attributes:
        action: the first action of the best sequence, to execute now, shape (D_a,).
        predicted_next_obs: the model's prediction after that action, shape (D_o,).
        cost: the best sequence's cost (cost_fn units, lower is better).
        sequence: the best action sequence, shape (H, D_a).
        predicted_obs: its predicted observations o_{t+1} … o_{t+H}, shape (H, D_o).
    """

    action: NDArray[np.float64]
    predicted_next_obs: NDArray[np.float64]
    cost: float
    sequence: NDArray[np.float64]
    predicted_obs: NDArray[np.float64]


def sample_action_sequences(rng: np.random.Generator, config: WaypointMPCConfig,
                            prior: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """N action sequences of horizon H, shape (N, H, D_a), within the action bounds.

    Args:
        rng: source of the samples.
        config: N, H, σ and the bounds.
        prior: the prior actions from the current step on (e.g. the rest of τ₀), shape
            (H', D_a), H' >= 1; the first H rows are used, a shorter prior is padded with its
            last row. Samples are prior + N(0, σ²), clipped to the bounds. Without a prior they
            are uniform over the bounds.

    Raises:
        InvalidActionError: the prior has the wrong shape or is not finite.
    """
    n, h, d = config.n_samples, config.horizon, config.action_dim
    lo, hi = np.array(config.action_low), np.array(config.action_high)
    if prior is None:
        return rng.uniform(lo, hi, size=(n, h, d))
    p = np.asarray(prior, dtype=np.float64)
    if p.ndim != 2 or p.shape[0] < 1 or p.shape[1] != d or not np.isfinite(p).all():
        raise InvalidActionError(
            f"the MPC prior must be finite actions of shape (H', {d}), H' >= 1; got shape "
            f"{p.shape}")
    if len(p) < h:
        p = np.concatenate([p, np.repeat(p[-1:], h - len(p), axis=0)])
    noise = rng.standard_normal((n, h, d)) * np.asarray(config.sigma)
    return np.clip(p[None, :h] + noise, lo, hi)


def rollout(model: StateDynamicsModel, obs: NDArray[np.float64],
            actions: NDArray[np.float64]) -> NDArray[np.float64]:
    """Predicted observations of N action sequences from one observation.

    Args:
        model: the dynamics model.
        obs: the current observation, shape (D_o,).
        actions: action sequences, shape (N, H, D_a).

    Returns:
        o_{t+1} … o_{t+H} of each sequence, shape (N, H, D_o).
    """
    n, h, _ = actions.shape
    current = np.broadcast_to(np.asarray(obs, dtype=np.float64), (n, len(obs)))
    out = np.empty((n, h, len(obs)))
    for step in range(h):
        current = model.predict(current, actions[:, step])
        out[:, step] = current
    return out


def plan_action(model: StateDynamicsModel, obs: NDArray[np.float64], cost_fn: CostFn,
                rng: np.random.Generator, config: WaypointMPCConfig,
                prior: NDArray[np.float64] | None = None) -> WaypointPlan:
    """One step of random-shooting MPC: the action to execute now.

    Args:
        model: dynamics model the samples are rolled out through.
        obs: the current observation, shape (D_o,).
        cost_fn: cost of each sequence from its predicted observations (N, H, D_o) and its
            actions (N, H, D_a), shape (N,); NaN/inf costs count as infinitely bad.
        rng: source of the samples (same generator state → same action).
        config: N, H, σ, action bounds.
        prior: the prior actions from the current step on, shape (H', D_a) (see
            :func:`sample_action_sequences`); None samples uniformly over the bounds.

    Raises:
        InvalidActionError: the observation or the prior is malformed.
        PlanningError: cost_fn returned another shape than (N,), or no finite cost.
    """
    o = np.asarray(obs, dtype=np.float64)
    if o.ndim != 1 or not np.isfinite(o).all():
        raise InvalidActionError(
            f"the MPC observation must be finite, of shape (D_o,); got shape {o.shape}")
    actions = sample_action_sequences(rng, config, prior)
    predicted = rollout(model, o, actions)
    costs = np.asarray(cost_fn(predicted, actions), dtype=np.float64)
    if costs.shape != (config.n_samples,):
        raise PlanningError(
            f"cost_fn must return shape ({config.n_samples},); got {costs.shape}")
    costs = np.where(np.isfinite(costs), costs, np.inf)
    best = int(np.argmin(costs))
    if not np.isfinite(costs[best]):
        raise PlanningError(f"no sampled action sequence of {config.n_samples} has a finite "
                            "cost (model predictions NaN/inf?)")
    sequence, future = _frozen(actions[best]), _frozen(predicted[best])
    return WaypointPlan(sequence[0], future[0], float(costs[best]), sequence, future)


def _frozen(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """A read-only copy."""
    y = np.array(x)
    y.flags.writeable = False
    return y

