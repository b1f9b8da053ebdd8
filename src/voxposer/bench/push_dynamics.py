"""Which dynamics model an episode's pushing MPC samples through, counted.

"heuristic" is the paper's (:class:`~voxposer.planning.dynamics.TranslationPush`: the object
translates with the push); "simulator" simulates every sampled push in a private copy of the
world (:class:`~voxposer.bench.sim_dynamics.SimulatedPush`): the error breakdown's
counterfactual for dynamics errors (paper Sec. 4.4). :class:`CountingPush` wraps either and
counts its predictions, so a record says whether its episode pushed anything.
"""

from __future__ import annotations

from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.planning.dynamics import DynamicsModel, PushBatch, PushPrediction, TranslationPush

#: ``dynamics`` values: the paper's heuristic, the simulator.
HEURISTIC: Final = "heuristic"
SIMULATOR: Final = "simulator"
DYNAMICS: Final = (HEURISTIC, SIMULATOR)


def push_dynamics(name: str, world: Any) -> DynamicsModel:
    """The dynamics model ``name`` (:data:`DYNAMICS`) for pushes in ``world``; ConfigError
    naming the known ones otherwise."""
    if name == HEURISTIC:
        return TranslationPush()
    if name == SIMULATOR:
        from voxposer.bench.sim_dynamics import SimulatedPush

        return SimulatedPush(world)
    raise ConfigError(f"unknown dynamics model {name!r}; choose one of: {', '.join(DYNAMICS)}")


class CountingPush:
    """A dynamics model that forwards to ``inner`` and counts its :meth:`predict` calls (one
    per MPC step). ``push_samples`` is the inner model's (how many pushes the MPC should
    sample: None leaves the MPC's default)."""

    def __init__(self, inner: DynamicsModel) -> None:
        self.inner = inner
        self.calls = 0
        self.push_samples: int | None = getattr(inner, "push_samples", None)

    def predict(self, centre: NDArray[np.float64], points: NDArray[np.float64],
                pushes: PushBatch) -> PushPrediction:
        """See :meth:`~voxposer.planning.dynamics.DynamicsModel.predict`."""
        self.calls += 1
        return self.inner.predict(centre, points, pushes)


__all__ = ["DYNAMICS", "HEURISTIC", "SIMULATOR", "CountingPush", "push_dynamics"]
