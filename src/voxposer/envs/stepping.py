"""Stepping a simulated world's physics with a divergence check.

A mixin of both worlds: :meth:`SteppedPhysicsMixin.advance` integrates through the world's own
:meth:`~SteppedPhysicsMixin._integrate` (an applied force, an object's latch), then checks that
the state stayed finite and MuJoCo flagged no bad positions, velocities or accelerations, drops
the cached observation and calls the step callbacks.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

import mujoco
import numpy as np

from voxposer.errors import SimulationUnstableError
from voxposer.perception.observation import Observation

#: MuJoCo's warnings that mean the state diverged.
BAD_STATE_WARNINGS: Final = (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL,
                             mujoco.mjtWarning.mjWARN_BADQACC)


class SteppedPhysicsMixin:
    """:meth:`advance` with the divergence check (needs the attributes declared below)."""

    model: mujoco.MjModel
    data: mujoco.MjData
    _obs: Observation | None
    _unstable: bool
    step_callbacks: list[Callable[[Any], None]]

    def _integrate(self, nsteps: int) -> None:
        """Step the physics ``nsteps`` times with the current commands (the world's own way)."""
        mujoco.mj_step(self.model, self.data, nstep=nsteps)

    def advance(self, nsteps: int) -> None:
        """Step the physics ``nsteps`` times with the current commands.

        Raises:
            SimulationUnstableError: the state became NaN/inf or MuJoCo flagged bad accelerations;
                the world must be reset before it can step again.
        """
        if self._unstable:
            raise SimulationUnstableError("the simulation diverged earlier; call reset() first")
        d = self.data
        bad_before = self._bad_count()
        self._integrate(nsteps)
        bad = self._bad_count() > bad_before
        if bad or not (np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel))):
            self._unstable = True
            raise SimulationUnstableError(
                f"simulation became unstable at t={d.time:.3f} s (NaN/inf or huge accelerations); "
                "call reset() before stepping again"
            )
        self._obs = None
        for callback in self.step_callbacks:
            callback(self)

    def _bad_count(self) -> int:
        return sum(int(self.data.warning[k].number) for k in BAD_STATE_WARNINGS)
