"""The task cost of online dynamics learning: the zero-shot programs' composed value maps.

The paper scores MPC samples of the learned model with the same value maps VoxPoser composed
zero-shot. Each executed sub-task of the zero-shot run is a :class:`~voxposer.learning.
zero_shot.Stage` (an entity and its cost map); the cost of a predicted observation sequence is
the current stage's cost at the entity's predicted positions (the end effector for "gripper",
the observed handle for a part). A rollout starts at stage 0 and moves to the next stage once the
observed entity is within ``reach_m`` of the stage's target (never back).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.learning.state import StateLayout
from voxposer.learning.zero_shot import Stage


@dataclass(frozen=True)
class TaskCostConfig:
    """Weights of the MPC's task cost.

    Attributes:
        reach_m: a stage is done when its entity is this close to the stage's target [m].
        final_weight: weight of the cost at the horizon's last step, beside the mean over all
            steps (1 = the mean alone).
        prior_weight: weight of the squared distance [m²] of a sample's end-effector targets
            from the prior's (0 = none; breaks ties while nothing but the arm moves).
    """

    reach_m: float = 0.03
    final_weight: float = 2.0
    prior_weight: float = 50.0

    def __post_init__(self) -> None:
        for name in ("reach_m", "final_weight", "prior_weight"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0:
                raise ConfigError(f"TaskCostConfig.{name} must be finite and >= 0, got {value!r}")


class TaskCost:
    """Stage-wise value-map cost over predicted observations.

    Args:
        stages: the zero-shot run's sub-tasks, in order (at least one).
        layout: where the end effector and the handle sit in an observation vector.
        config: weights.
    """

    def __init__(self, stages: tuple[Stage, ...], layout: StateLayout,
                 config: TaskCostConfig | None = None) -> None:
        if not stages:
            raise ConfigError("a task cost needs at least one zero-shot stage")
        self.stages = stages
        self.layout = layout
        self.config = config or TaskCostConfig()
        #: how far [m], shape (3,), this episode's object sits from where the zero-shot run saw
        #: it (the handle's observed displacement); the maps are read that much shifted
        self.shift = np.zeros(3)

    def entity_positions(self, obs: NDArray[np.float64], stage: int) -> NDArray[np.float64]:
        """The stage's entity positions [m] in observations ``obs``, shape (..., D_o) → (..., 3),
        in the zero-shot run's frame (less :attr:`shift`)."""
        return obs[..., self.layout.entity_slice(self.stages[stage].entity)] - self.shift

    def advance(self, obs: NDArray[np.float64], stage: int) -> int:
        """The stage after observing ``obs`` (shape (D_o,)) while in ``stage``."""
        while stage < len(self.stages) - 1:
            _, dist = self.stages[stage].lookup(self.entity_positions(obs, stage)[None])
            if float(dist[0]) > self.config.reach_m:
                break
            stage += 1
        return stage

    def remaining(self, obs: NDArray[np.float64], stage: int) -> float:
        """Distance [m] of the stage's entity from the stage's target in ``obs`` (D_o,)."""
        _, dist = self.stages[stage].lookup(self.entity_positions(obs, stage)[None])
        return float(dist[0])

    def __call__(self, predicted: NDArray[np.float64], actions: NDArray[np.float64], stage: int,
                 prior_targets: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """Cost of N predicted sequences, shape (N,).

        Args:
            predicted: predicted observations, shape (N, H, D_o).
            actions: the sampled actions, shape (N, H, D_a) (unused but for the prior term).
            stage: the current stage.
            prior_targets: the prior's end-effector targets [m], shape (H, 3), if any (world
                frame: already shifted to this episode's object).
        """
        cost, _ = self.stages[stage].lookup(self.entity_positions(predicted, stage))
        cost = cost.astype(np.float64)  # (N, H)
        total = cost.mean(axis=1) + (self.config.final_weight - 1.0) * cost[:, -1]
        if prior_targets is not None and self.config.prior_weight > 0:
            ee = predicted[..., self.layout.entity_slice("gripper")]  # world frame, as the targets
            gap = ((ee - prior_targets[None]) ** 2).sum(axis=2).mean(axis=1)
            total = total + self.config.prior_weight * gap
        return np.asarray(total, dtype=np.float64)


__all__ = ["TaskCost", "TaskCostConfig"]
