"""What one ``execute`` call did (:class:`ExecutionResult`), and the map sources it takes.

Shared by the closed-loop controller (:mod:`voxposer.control.closed_loop`) and its pushing loop
(:mod:`voxposer.control.pushing_loop`), which neither imports the other's module for it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from voxposer.planning.planner import Plan

StopReason = Literal["reached", "end_of_travel", "stalled", "timeout", "planning_failed"]
MapSource = Callable[[], NDArray[Any]] | NDArray[Any] | None


@dataclass
class ExecutionResult:
    """What one ``execute`` call did.

    Attributes:
        success: the entity reached the affordance target.
        reason: why the loop stopped.
        message: a sentence for people (and for the LLM when it retries).
        entity: the entity's name.
        replans: planning steps taken.
        sim_time: simulated time spent [s].
        wall_time: wall time spent [s].
        final_distance: entity-to-target distance at the end [m].
        entity_path: the entity's observed positions, one per replan [m], shape (R, 3).
        trace: end-effector positions after every control period [m], shape (T, 3), and
            ``trace_time``, shape (T,), their simulation times [s] (for speed and clearance
            checks over the whole motion).
        first_plan: the first plan, from where the entity started (for pictures).
        last_plan: the last plan.
        timings_ms: per replan, wall time of observe, maps, plan [ms].
        missed_moves: the robot's moves (of pushes) that ended away from their targets, and
            ``worst_miss_m`` the largest such distance [m]; the message reports them.
    """

    success: bool
    reason: StopReason
    message: str
    entity: str
    replans: int = 0
    sim_time: float = 0.0
    wall_time: float = 0.0
    final_distance: float = float("inf")
    entity_path: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))
    trace: list[NDArray[np.float64]] = field(default_factory=list)
    trace_time: list[float] = field(default_factory=list)
    started_wall: float = field(default_factory=time.perf_counter, repr=False)
    started_sim: float = field(default=0.0, repr=False)
    _path: list[NDArray[np.float64]] = field(default_factory=list, repr=False)
    first_plan: Plan | None = None
    last_plan: Plan | None = None
    timings_ms: list[dict[str, float]] = field(default_factory=list)
    missed_moves: int = 0
    worst_miss_m: float = 0.0

    @property
    def replan_hz(self) -> float:
        """Replanning steps per wall second, observation + maps + planning included (median)."""
        if not self.timings_ms:
            return 0.0
        per = np.median([sum(t.values()) for t in self.timings_ms]) / 1000.0
        return float(1.0 / per) if per > 0 else float("inf")


def evaluate(source: Any) -> Any:
    """A map source's value: the result of calling it, or the value itself."""
    return source() if callable(source) else source
