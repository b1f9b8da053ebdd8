"""The state-dynamics protocol the waypoint MPC samples through (paper Sec. 3.4, Table 3).

A state model g(o_t, a_t) → o_{t+1} predicts the next observation vector for a batch of
observations and actions, e.g. o = (end-effector position [m] (3), gripper (1), handle angle
[rad], door angle [rad]) and a = (end-effector displacement [m] (3), gripper command). The learned
MLP (:class:`~voxposer.planning.dynamics.mlp.MLPDynamics`), a known linear system
(:class:`~voxposer.planning.dynamics.linear.LinearDynamics`) or the simulator itself implement
it; :func:`voxposer.planning.waypoint_mpc.plan_action` never knows which it uses.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray


@runtime_checkable
class StateDynamicsModel(Protocol):
    """Predicts next observations, batched (no Python loop per sample)."""

    def predict(self, obs: NDArray[np.float64],
                actions: NDArray[np.float64]) -> NDArray[np.float64]:
        """The next observation after each action.

        Args:
            obs: observations, shape (S, D_o).
            actions: actions, shape (S, D_a).

        Returns:
            predicted next observations, shape (S, D_o).
        """
        ...
