"""What ``execute(...)`` in composer code hands over: an :class:`ExecutionRequest`.

Composer code calls ``execute(movable, affordance_map=..., avoidance_map=..., ...)``; the LMP
context turns every argument into a zero-argument callable that re-evaluates it against the
current observation (the cached program is re-run, no new LLM call), and passes them to an
:class:`ExecuteHandler`. The closed-loop executor (planner + controller, replanning each step) is a
separate component; :class:`RecordingHandler` is the simple one for tests and the CLI.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

#: The map keyword arguments ``execute`` accepts.
MAP_ARGUMENTS = ("affordance_map", "avoidance_map", "rotation_map", "velocity_map", "gripper_map")

MapFn = Callable[[], NDArray[np.floating]]


@dataclass(frozen=True)
class ExecutionRequest:
    """One ``execute`` call of a sub-task.

    Attributes:
        subtask: the composer query that produced it ("grasp the blue block").
        movable: returns the entity of interest (an ``ObjectView``) as currently observed.
        maps: argument name (``"affordance_map"``…) → callable returning the current map,
            shape ``grid.shape`` (``(*grid.shape, 4)`` for rotation). Missing maps use defaults.
    """

    subtask: str
    movable: Callable[[], Any]
    maps: dict[str, MapFn] = field(default_factory=dict)


class ExecuteHandler(Protocol):
    """Carries out sub-tasks. Implementations may re-evaluate the callables at every step."""

    def execute(self, request: ExecutionRequest) -> Any:
        """Move ``request.movable`` as the maps say; raise on failure (never fail silently)."""

    def reset_to_default_pose(self) -> Any:
        """Move the robot to its rest pose."""


@dataclass
class RecordingHandler:
    """Records requests and evaluates each map once (no robot). For tests and ``voxposer lmp``.

    Attributes:
        requests: every request received, in order.
        evaluated: per request, ``{"movable": ObjectView, "<map>": array}`` from one evaluation.
        resets: how many times ``reset_to_default_pose`` was called.
    """

    requests: list[ExecutionRequest] = field(default_factory=list)
    evaluated: list[dict[str, Any]] = field(default_factory=list)
    resets: int = 0
    evaluate: bool = True

    def execute(self, request: ExecutionRequest) -> None:
        self.requests.append(request)
        if self.evaluate:
            out: dict[str, Any] = {"movable": request.movable()}
            out.update({name: fn() for name, fn in request.maps.items()})
            self.evaluated.append(out)

    def reset_to_default_pose(self) -> None:
        self.resets += 1
