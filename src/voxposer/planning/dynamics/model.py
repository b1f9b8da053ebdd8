"""The dynamics-model protocol the MPC samples through (paper Sec. 4 "Dynamics Model").

A model predicts where a pushed object ends up for a batch of candidate pushes. The paper's
heuristic (the object translates with the push) is :class:`~voxposer.planning.dynamics.
translation.TranslationPush`; a learned model (paper Table 3) or the simulator itself implement
the same protocol, and :func:`voxposer.planning.mpc.random_shooting` never knows which it uses.
"""

from __future__ import annotations

from typing import NamedTuple, Protocol

import numpy as np
from numpy.typing import NDArray


class PushBatch(NamedTuple):
    """S candidate pushes.

    Attributes:
        contacts: contact points on the object's surface [m], shape (S, 3).
        directions: unit push directions in the table plane, shape (S, 3).
        distances: push distances [m], shape (S,).
    """

    contacts: NDArray[np.float64]
    directions: NDArray[np.float64]
    distances: NDArray[np.float64]


class PushPrediction(NamedTuple):
    """A model's prediction for a :class:`PushBatch`.

    Attributes:
        centres: the object's centre after each push [m], shape (S, 3).
        points: the given object points after each push [m], shape (S, P, 3).
    """

    centres: NDArray[np.float64]
    points: NDArray[np.float64]


class DynamicsModel(Protocol):
    """Predicts the outcome of pushes, batched (no Python loop per sample)."""

    def predict(self, centre: NDArray[np.float64], points: NDArray[np.float64],
                pushes: PushBatch) -> PushPrediction:
        """Where the object (centre [m], shape (3,); points [m], shape (P, 3)) ends up after
        each push of ``pushes``."""
        ...
