"""Every benchmark task as a registered Gymnasium environment, so other methods can be run on
the suite: ``gym.make("voxposer/PushToPos-v0", split="unseen")``.

``reset(seed=s)`` draws the task's episode ``s`` exactly as the benchmark does
(:func:`~voxposer.bench.task.reset_episode`: attributes, layout, start pose) and returns the
instruction in ``info``. Actions and observations are those of
:class:`~voxposer.envs.gym_env.TabletopEnv` (an end-effector pose and gripper per controller
period). After every step the task's own success check judges the episode so far:
``info["success"]`` and ``info["reason"]``; the reward is 1 on success, when the episode also
terminates.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from numpy.typing import NDArray

from voxposer.bench.attributes import check_split
from voxposer.bench.config import Tolerances
from voxposer.bench.task import EpisodeSetup, reset_episode
from voxposer.bench.tasks import get_task
from voxposer.bench.trace import TraceRecorder
from voxposer.envs.gym_env import TabletopEnv


class TaskEnv(TabletopEnv):
    """One benchmark task (see the module docstring).

    Args:
        task: the task's name (:data:`~voxposer.bench.tasks.TASKS`).
        split: "seen" or "unseen" attributes.
        tolerances: the success thresholds (the benchmark's by default).
        **kwargs: passed to :class:`TabletopEnv` (``images``, ``max_steps``, ``render_mode``).
    """

    def __init__(self, task: str, split: str = "seen", tolerances: Tolerances | None = None,
                 **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.task = get_task(task)
        self.split = check_split(split)
        self.tolerances = tolerances or Tolerances()
        self.setup: EpisodeSetup | None = None
        self._recorder: TraceRecorder | None = None

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
        """Episode ``seed`` of the task (a seed drawn from ``np_random`` when None)."""
        gym.Env.reset(self, seed=seed)
        episode = int(seed) if seed is not None else int(self.np_random.integers(2**31 - 1))
        if self._recorder is not None:
            self._recorder.__exit__()
        self.setup = reset_episode(self.task, self.world, self.split, episode, self.tolerances)
        self._recorder = TraceRecorder(self.world, self.task.tracked(self.setup.attributes))
        self._recorder.__enter__()
        self._steps = 0
        return self._observation(), {"instruction": self.setup.instruction,
                                     "attributes": dict(self.setup.attributes), "seed": episode}

    def step(self, action: NDArray[np.float64]
             ) -> tuple[dict[str, NDArray[Any]], float, bool, bool, dict[str, Any]]:
        """One controller period; ``info["success"]`` is the task's check so far."""
        if self.setup is None or self._recorder is None:
            raise gym.error.ResetNeeded("call reset() before step()")
        obs, _, _, truncated, info = super().step(action)
        verdict = self.task.check(self.world, self._recorder.trace(), self.setup.attributes,
                                  self.tolerances)
        info.update(success=bool(verdict.success), reason=verdict.reason)
        return obs, float(verdict.success), bool(verdict.success), truncated, info

    def close(self) -> None:
        """Detach the trace recorder and release the world."""
        if self._recorder is not None:
            self._recorder.__exit__()
            self._recorder = None
        super().close()


__all__ = ["TaskEnv"]
