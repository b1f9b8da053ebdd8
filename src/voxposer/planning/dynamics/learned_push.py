"""A learned pushing model: an MLP over pushes in the push's own frame (issue: Table 3's MLP,
used in the benchmark's pushing tasks beside the paper's heuristic).

A push is described in its frame — ``d`` the unit push direction in the table plane, ``s`` the
sideways axis (``d`` turned +90° about z), the origin at the object's centre — by the action
``(lateral, depth, distance, incidence)``: the contact's offset along ``s`` and along ``d`` from
the centre [m], the push distance [m] and the angle [rad, ±π/4] from the object's nearest face
normal to ``d`` (a flat pusher meeting a face at an angle turns the block until they align:
measured in the simulator, up to ~30° for a 5 cm push). The object's state in that frame is ``(along, across,
yaw)`` [m, m, rad], zero before the push; :class:`~voxposer.planning.dynamics.mlp.MLPDynamics`
learns its change. :class:`LearnedPush` implements :class:`~voxposer.planning.dynamics.
DynamicsModel` with it: batched, one forward pass for all S pushes (the MPC's 10,000 samples
cost one matrix product per layer), the points carried by the predicted rigid motion.
"""

from __future__ import annotations

from pathlib import Path
from typing import Final

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.planning.dynamics.mlp import MLPDynamics
from voxposer.planning.dynamics.model import PushBatch, PushPrediction
from voxposer.planning.push_primitive import footprint

#: sizes of the push-frame state (along, across, yaw) and action (lateral, depth, distance,
#: incidence).
STATE_DIM: Final = 3
ACTION_DIM: Final = 4


def face_normal_angle(points: NDArray[np.float64]) -> float:
    """The angle [rad] of a face normal of a box-like object's footprint (points [m], shape
    (P, 3)), modulo π/2: from the 4-fold symmetry of its outline (corners lie farthest out)."""
    ring = footprint(np.asarray(points, dtype=np.float64).reshape(-1, 3))
    rel = ring[:, :2] - ring[:, :2].mean(axis=0)
    r2 = np.einsum("ij,ij->i", rel, rel)
    theta = np.arctan2(rel[:, 1], rel[:, 0])
    corner = float(np.angle(np.sum(r2 * r2 * np.exp(4j * theta)))) / 4.0
    return corner + np.pi / 4.0


def push_actions(centre: NDArray[np.float64], pushes: PushBatch,
                 points: NDArray[np.float64]) -> NDArray[np.float64]:
    """The pushes of the object with ``points`` [m], shape (P, 3), in their own frames:
    (lateral, depth, distance, incidence), shape (S, 4) (see the module)."""
    d = np.asarray(pushes.directions, dtype=np.float64)[:, :2]
    d = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
    s = np.column_stack([-d[:, 1], d[:, 0]])
    rel = np.asarray(pushes.contacts, dtype=np.float64)[:, :2] - np.asarray(centre)[:2]
    quarter = np.pi / 2.0
    incidence = (np.arctan2(d[:, 1], d[:, 0]) - face_normal_angle(points) + quarter / 2) \
        % quarter - quarter / 2
    return np.column_stack([np.einsum("ij,ij->i", rel, s), np.einsum("ij,ij->i", rel, d),
                            np.asarray(pushes.distances, dtype=np.float64), incidence])


def push_outcome(centre: NDArray[np.float64], direction: NDArray[np.float64],
                 final_centre: NDArray[np.float64], yaw: float) -> NDArray[np.float64]:
    """An observed push in its frame: (along, across, yaw) [m, m, rad], shape (3,), of an
    object moved from ``centre`` to ``final_centre`` [m] and turned by ``yaw`` [rad]."""
    d = np.asarray(direction, dtype=np.float64)[:2]
    d = d / max(float(np.linalg.norm(d)), 1e-12)
    move = np.asarray(final_centre, dtype=np.float64)[:2] - np.asarray(centre)[:2]
    return np.array([move @ d, move @ np.array([-d[1], d[0]]), yaw])


class LearnedPush:
    """Pushes predicted by a trained :class:`MLPDynamics` of (3, 4) dims (see the module).

    Args:
        model: the trained network (``from_file`` of what ``voxposer learn-push`` saved).

    Raises:
        ConfigError: the network has other dims than (state 3, action 4).

    Attributes:
        handles_parts: False — it is learned on free blocks, so the pushing loop keeps the
            heuristic for a sliding part (a drawer moves exactly along its axis).
    """

    handles_parts = False

    def __init__(self, model: MLPDynamics) -> None:
        if (model.obs_dim, model.action_dim) != (STATE_DIM, ACTION_DIM):
            raise ConfigError(f"a push model needs (state, action) dims (3, 4); got "
                              f"({model.obs_dim}, {model.action_dim})")
        self.model = model

    @classmethod
    def from_file(cls, path: str | Path) -> LearnedPush:
        """The model saved at ``path``; ConfigError naming it when there is none."""
        if not Path(path).is_file():
            raise ConfigError(f"no push model at {path} (write one with voxposer learn-push)")
        return cls(MLPDynamics.from_file(path))

    def predict(self, centre: NDArray[np.float64], points: NDArray[np.float64],
                pushes: PushBatch) -> PushPrediction:
        """See :meth:`~voxposer.planning.dynamics.DynamicsModel.predict`."""
        c = np.asarray(centre, dtype=np.float64).reshape(3)
        actions = push_actions(c, pushes, points)
        out = self.model.predict(np.zeros((len(actions), STATE_DIM)), actions)
        d = np.asarray(pushes.directions, dtype=np.float64)[:, :2]
        d = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
        s = np.column_stack([-d[:, 1], d[:, 0]])
        shift = out[:, :1] * d + out[:, 1:2] * s  # (S, 2)
        centres = np.tile(c, (len(actions), 1))
        centres[:, :2] += shift
        cos, sin = np.cos(out[:, 2]), np.sin(out[:, 2])
        rel = np.asarray(points, dtype=np.float64).reshape(-1, 3) - c  # (P, 3)
        moved = np.empty((len(actions), len(rel), 3))
        moved[:, :, 0] = cos[:, None] * rel[:, 0] - sin[:, None] * rel[:, 1]
        moved[:, :, 1] = sin[:, None] * rel[:, 0] + cos[:, None] * rel[:, 1]
        moved[:, :, 2] = rel[:, 2]
        return PushPrediction(centres, moved + centres[:, None, :])


__all__ = ["ACTION_DIM", "STATE_DIM", "LearnedPush", "push_actions", "push_outcome"]
