"""One episode of online interaction: observe o_t, choose a_t, track it, observe o_{t+1}.

An action a_t = (Δx, Δy, Δz [m], gripper command) moves the end-effector's target by Δ from
where the end effector is, and is tracked for ``step_duration_s`` of simulated time through the
:class:`~voxposer.robot.Robot` protocol. The episode ends when the object is open (the task's
own check), or after ``max_steps`` actions.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError, SimulationUnstableError, UnreachablePoseError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.learning.state import StateObserver
from voxposer.learning.task_cost import TaskCost

#: End-effector targets are kept this far inside the workspace box [m].
_MARGIN_M = 0.01


@dataclass(frozen=True)
class RolloutConfig:
    """How actions are executed.

    Attributes:
        step_duration_s: simulated time one action is tracked [s].
        max_steps: actions per episode.
        action_bound_m: the largest |Δ| per axis of one action [m] (the action space's box).
    """

    step_duration_s: float = 0.25
    max_steps: int = 100
    action_bound_m: float = 0.03

    def __post_init__(self) -> None:
        if not self.step_duration_s > 0:
            raise ConfigError(f"RolloutConfig.step_duration_s must be > 0, got "
                              f"{self.step_duration_s!r}")
        if self.max_steps < 1:
            raise ConfigError(f"RolloutConfig.max_steps must be >= 1, got {self.max_steps!r}")
        if not self.action_bound_m > 0:
            raise ConfigError(f"RolloutConfig.action_bound_m must be > 0, got "
                              f"{self.action_bound_m!r}")

    @property
    def action_low(self) -> NDArray[np.float64]:
        """Lower corner of the action box, shape (4,)."""
        b = self.action_bound_m
        return np.array([-b, -b, -b, 0.0])

    @property
    def action_high(self) -> NDArray[np.float64]:
        """Upper corner of the action box, shape (4,)."""
        b = self.action_bound_m
        return np.array([b, b, b, 1.0])


class Policy(Protocol):
    """Chooses actions during an episode."""

    def act(self, obs: NDArray[np.float64], step: int, stage: int,
            rng: np.random.Generator) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(a_t, shape (4,), the end-effector orientation (x, y, z, w) to hold while it runs)."""
        ...

    def stage_at(self, step: int) -> int:
        """The least stage of the task cost at ``step`` (a prior's own sub-task then; 0 when
        only progress moves the stage on)."""
        ...


class ArticulatedScene(Protocol):
    """What a rollout needs of the world besides the robot protocol."""

    @property
    def control_period(self) -> float: ...

    @property
    def grid(self) -> VoxelGrid: ...

    @property
    def time(self) -> float: ...

    def get_ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...

    def step(self, position: Any, quat_xyzw: Any, gripper: float | None = None,
             speed_scale: float = 1.0) -> Any: ...

    def success(self) -> tuple[bool, str]: ...


@dataclass(frozen=True)
class Episode:
    """What one episode saw and did.

    Attributes:
        obs: observations o_0 … o_T, shape (T + 1, D_o).
        actions: actions a_0 … a_{T-1}, shape (T, 4).
        success: the task's check at the end.
        reason: its words (the measured opening and the threshold), or what stopped the episode.
        sim_time_s: simulated interaction time [s].
        wall_time_s: wall time [s].
        stage: the last stage of the task cost reached.
    """

    obs: NDArray[np.float64]
    actions: NDArray[np.float64]
    success: bool
    reason: str
    sim_time_s: float
    wall_time_s: float
    stage: int


def run_episode(world: ArticulatedScene, observer: StateObserver, policy: Policy,
                cost: TaskCost, config: RolloutConfig, rng: np.random.Generator) -> Episode:
    """Run one episode from the world's current (freshly reset) state."""
    start_sim, start_wall = world.time, time.perf_counter()
    observer.reset()
    obs = [observer.observe()]
    actions: list[NDArray[np.float64]] = []
    stage, reason = 0, ""
    n_control = max(1, round(config.step_duration_s / world.control_period))
    success = False
    for step in range(config.max_steps):
        action, quat = policy.act(obs[-1], step, stage, rng)
        action = np.clip(action, config.action_low, config.action_high)
        ee, _ = world.get_ee_pose()
        lo, hi = world.grid.bounds_min + _MARGIN_M, world.grid.bounds_max - _MARGIN_M
        target = np.clip(ee + action[:3], lo, hi)  # the robot refuses targets off its workspace
        grip = 1.0 if action[3] >= 0.5 else 0.0
        try:
            for _ in range(n_control):
                world.step(target, quat, grip)
        except (UnreachablePoseError, SimulationUnstableError) as exc:
            reason = f"stopped at action {step}: {exc}"
            actions.append(action)
            obs.append(observer.observe())
            break
        actions.append(action)
        obs.append(observer.observe())
        stage = max(cost.advance(obs[-1], stage), policy.stage_at(step + 1))
        success, reason = world.success()
        if success:
            break
    if not reason:
        success, reason = world.success()
    return Episode(obs=np.asarray(obs), actions=np.asarray(actions).reshape(-1, 4),
                   success=success, reason=reason, sim_time_s=world.time - start_sim,
                   wall_time_s=time.perf_counter() - start_wall, stage=stage)


__all__ = ["ArticulatedScene", "Episode", "Policy", "RolloutConfig", "run_episode"]
