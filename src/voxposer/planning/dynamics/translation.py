"""The paper's heuristic pushing dynamics: the object translates along the push."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from voxposer.planning.dynamics.model import PushBatch, PushPrediction


def translate_points(points: NDArray, directions: NDArray, distances: NDArray) -> NDArray:
    """Object points after pushes that translate them (batched).

    Args:
        points: object points [m], shape (P, 3).
        directions: unit push directions, shape (S, 3).
        distances: push distances [m], shape (S,).

    Returns:
        predicted points [m], shape (S, P, 3).
    """
    return points[None, :, :] + (directions * distances[:, None])[:, None, :]


class TranslationPush:
    """Every point of the object moves by the push direction × the push distance (the contact
    point and friction are ignored), as in the paper's simulated and real experiments."""

    def predict(self, centre: NDArray[np.float64], points: NDArray[np.float64],
                pushes: PushBatch) -> PushPrediction:
        """See :meth:`DynamicsModel.predict`."""
        centres = centre + pushes.directions * pushes.distances[:, None]
        return PushPrediction(centres, translate_points(points, pushes.directions,
                                                        pushes.distances))
