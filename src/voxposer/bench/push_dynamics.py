"""Which dynamics model an episode's pushing MPC samples through, counted.

"heuristic" is the paper's (:class:`~voxposer.planning.dynamics.TranslationPush`: the object
translates with the push); "simulator" simulates every sampled push in a private copy of the
world (:class:`~voxposer.bench.sim_dynamics.SimulatedPush`): the error breakdown's
counterfactual for dynamics errors (paper Sec. 4.4); "learned" is an MLP trained on simulated
pushes (:class:`~voxposer.planning.dynamics.learned_push.LearnedPush`, ``voxposer
learn-push``). :class:`CountingPush` wraps either and
counts its predictions, so a record says whether its episode pushed anything.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.planning.dynamics import DynamicsModel, PushBatch, PushPrediction, TranslationPush

#: ``dynamics`` values: the paper's heuristic, the simulator.
HEURISTIC: Final = "heuristic"
SIMULATOR: Final = "simulator"
LEARNED: Final = "learned"
DYNAMICS: Final = (HEURISTIC, SIMULATOR, LEARNED)


def check_dynamics_options(name: str, push_model: str | Path | None) -> None:
    """ConfigError unless ``name`` is one of :data:`DYNAMICS` and a push model file is given
    exactly when it is "learned" (naming the option and the path)."""
    if name not in DYNAMICS:
        raise ConfigError(f"unknown dynamics model {name!r}; choose one of: {', '.join(DYNAMICS)}")
    if name == LEARNED and push_model is None:
        raise ConfigError("--dynamics learned needs --push-model PATH (voxposer learn-push "
                          "writes push_model.npz)")
    if name != LEARNED and push_model is not None:
        raise ConfigError(f"--push-model {str(push_model)!r} is for --dynamics learned only; "
                          f"got --dynamics {name}")
    if push_model is not None and not Path(push_model).is_file():
        raise ConfigError(f"no push model at {push_model} (voxposer learn-push writes one)")


def push_dynamics(name: str, world: Any, push_model: str | Path | None = None) -> DynamicsModel:
    """The dynamics model ``name`` (:data:`DYNAMICS`) for pushes in ``world`` (``push_model``:
    the learned model's file); ConfigError naming what is wrong otherwise."""
    check_dynamics_options(name, push_model)
    if name == SIMULATOR:
        from voxposer.bench.sim_dynamics import SimulatedPush

        return SimulatedPush(world)
    if name == LEARNED and push_model is not None:
        from voxposer.planning.dynamics.learned_push import LearnedPush

        return LearnedPush.from_file(push_model)
    return TranslationPush()


class CountingPush:
    """A dynamics model that forwards to ``inner`` and counts its :meth:`predict` calls (one
    per MPC step). ``push_samples`` is the inner model's (how many pushes the MPC should
    sample: None leaves the MPC's default)."""

    def __init__(self, inner: DynamicsModel) -> None:
        self.inner = inner
        self.calls = 0
        self.push_samples: int | None = getattr(inner, "push_samples", None)
        self.handles_parts: bool = getattr(inner, "handles_parts", True)

    def predict(self, centre: NDArray[np.float64], points: NDArray[np.float64],
                pushes: PushBatch) -> PushPrediction:
        """See :meth:`~voxposer.planning.dynamics.DynamicsModel.predict`."""
        self.calls += 1
        return self.inner.predict(centre, points, pushes)


__all__ = ["DYNAMICS", "HEURISTIC", "LEARNED", "SIMULATOR", "CountingPush",
           "check_dynamics_options", "push_dynamics"]
