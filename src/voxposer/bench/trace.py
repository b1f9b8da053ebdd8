"""What happened during an episode: end effector, gripper and chosen objects over time.

:class:`TraceRecorder` hooks :attr:`TabletopWorld.step_callbacks`, so it sees every physics
advance whatever moved the robot (closed-loop ``execute``, pushing primitives, or the
LLM + Primitives baseline's ``move_to_pose``) — one sample per controller period (20 ms).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray


@dataclass
class Trace:
    """Samples of an episode, in simulation time order.

    Attributes:
        time: simulation time [s], shape (T,).
        ee: end-effector position [m], shape (T, 3).
        gripper: commanded gripper state (1 closed, 0 open), shape (T,).
        objects: object name → position [m], shape (T, 3).
    """

    time: NDArray[np.float64]
    ee: NDArray[np.float64]
    gripper: NDArray[np.float64]
    objects: dict[str, NDArray[np.float64]] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.time)

    def speed(self, window_s: float) -> NDArray[np.float64]:
        """End-effector speed [m/s] at each sample over the preceding ``window_s``, shape (T,)
        (NaN where the window reaches before the first sample)."""
        out = np.full(len(self.time), np.nan)
        if len(self.time) < 2:
            return out
        start = np.searchsorted(self.time, self.time - window_s, side="right") - 1
        ok = start >= 0
        k = np.nonzero(ok)[0]
        j = start[ok]
        dt = self.time[k] - self.time[j]
        good = dt > 1e-9
        out[k[good]] = np.linalg.norm(self.ee[k[good]] - self.ee[j[good]], axis=1) / dt[good]
        return out


class TraceRecorder:
    """Records a :class:`Trace` from a world while attached (context manager).

    Args:
        world: a :class:`voxposer.envs.TabletopWorld` (``step_callbacks``, ``get_ee_pose``,
            ``get_gripper_state``, ``object_position``).
        objects: names of objects whose ground-truth positions to record.
    """

    def __init__(self, world: Any, objects: tuple[str, ...] = ()) -> None:
        self.world = world
        self.names = tuple(objects)
        self._t: list[float] = []
        self._ee: list[NDArray[np.float64]] = []
        self._g: list[float] = []
        self._obj: dict[str, list[NDArray[np.float64]]] = {n: [] for n in self.names}
        self._sample(world)

    def _sample(self, world: Any) -> None:
        self._t.append(float(world.data.time))
        self._ee.append(world.get_ee_pose()[0])
        self._g.append(float(world.get_gripper_state()))
        for name in self.names:
            self._obj[name].append(world.object_position(name))

    def __enter__(self) -> TraceRecorder:
        self.world.step_callbacks.append(self._sample)
        return self

    def __exit__(self, *exc: object) -> None:
        if self._sample in self.world.step_callbacks:
            self.world.step_callbacks.remove(self._sample)

    def trace(self) -> Trace:
        """The samples so far."""
        return Trace(
            np.asarray(self._t, dtype=np.float64),
            np.asarray(self._ee, dtype=np.float64).reshape(-1, 3),
            np.asarray(self._g, dtype=np.float64),
            {n: np.asarray(v, dtype=np.float64).reshape(-1, 3) for n, v in self._obj.items()},
        )


def snapshot(world: Any, objects: tuple[str, ...] = ()) -> Trace:
    """A one-sample trace of the world as it is now (e.g. right after reset)."""
    return TraceRecorder(world, objects).trace()
