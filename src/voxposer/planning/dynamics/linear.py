"""A known linear system o_{t+1} = A o_t + B a_t (+ c): a reference :class:`StateDynamicsModel`
for tests, benchmarks and systems whose dynamics are known."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import DimensionMismatchError


class LinearDynamics:
    """o_{t+1} = A o_t + B a_t + c.

    Args:
        a: state matrix, shape (D_o, D_o).
        b: input matrix, shape (D_o, D_a).
        c: constant drift, shape (D_o,) (default zero).

    Raises:
        DimensionMismatchError: the matrices' shapes do not fit together.
    """

    def __init__(self, a: NDArray[np.float64], b: NDArray[np.float64],
                 c: NDArray[np.float64] | None = None) -> None:
        self.a = np.array(a, dtype=np.float64)
        self.b = np.array(b, dtype=np.float64)
        d_o = self.a.shape[0] if self.a.ndim == 2 else -1
        self.c = np.zeros(max(d_o, 0)) if c is None else np.array(c, dtype=np.float64)
        if (self.a.ndim != 2 or self.a.shape != (d_o, d_o) or self.b.ndim != 2
                or self.b.shape[0] != d_o or self.c.shape != (d_o,)):
            raise DimensionMismatchError(
                f"LinearDynamics needs A (D_o, D_o), B (D_o, D_a), c (D_o,); got A "
                f"{self.a.shape}, B {self.b.shape}, c {self.c.shape}")

    @property
    def obs_dim(self) -> int:
        """D_o."""
        return int(self.a.shape[0])

    @property
    def action_dim(self) -> int:
        """D_a."""
        return int(self.b.shape[1])

    def predict(self, obs: NDArray[np.float64],
                actions: NDArray[np.float64]) -> NDArray[np.float64]:
        """See :meth:`StateDynamicsModel.predict`: obs (S, D_o), actions (S, D_a) → (S, D_o)."""
        return np.asarray(obs) @ self.a.T + np.asarray(actions) @ self.b.T + self.c
