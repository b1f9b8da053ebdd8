"""The bridge from language model programs to the robot: ``execute`` calls run in closed loop.

Composer code calls ``execute(movable, affordance_map=…, …)``; the LMP runtime turns the
arguments into re-evaluable callables (:class:`voxposer.lmp.handoff.ExecutionRequest`) and hands
them to an executor. :class:`RobotHandoff` runs each request with the
:class:`~voxposer.control.closed_loop.ClosedLoopController` on a robot and a perceiver, keeps
every result, writes an
HTML picture of the composed maps and the planned path per sub-task, and raises
:class:`~voxposer.errors.ExecutionFailedError` when a sub-task does not reach its target (never
a silent failure).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from voxposer.control.closed_loop import ClosedLoopController
from voxposer.control.config import ExecutorConfig
from voxposer.control.execution_result import ExecutionResult
from voxposer.errors import ExecutionFailedError
from voxposer.perception.perceiver import Perceiver
from voxposer.planning.dynamics import DynamicsModel
from voxposer.robot import Robot

log = logging.getLogger(__name__)


@dataclass
class SubtaskRecord:
    """One executed sub-task: its query, result and picture."""

    subtask: str
    result: ExecutionResult
    picture: Path | None = None


@dataclass
class RobotHandoff:
    """Implements the LMP runtime's ``ExecuteHandler`` protocol on a robot.

    Attributes:
        robot: the arm (:class:`voxposer.robot.Robot`, e.g. :class:`voxposer.envs.TabletopWorld`).
        perceiver: what detects the entity at every replan (:class:`voxposer.perception.Perceiver`).
        rng: randomness for the pushing MPC.
        config: closed-loop parameters.
        picture_dir: where to write ``subtask_<k>.html`` pictures (None = none).
        on_replan: forwarded to the closed-loop executor (live progress, disturbances).
        push_model: the pushing MPC's dynamics model (None: the paper's heuristic).
        records: every sub-task executed, in order.
        keep_going: a sub-task that misses its target is recorded and the program goes on
            (recording a zero-shot trajectory whole), instead of raising.
    """

    robot: Robot
    perceiver: Perceiver
    rng: np.random.Generator
    config: ExecutorConfig = field(default_factory=ExecutorConfig)
    picture_dir: Path | None = None
    on_replan: Callable[[ExecutionResult, Any], None] | None = None
    push_model: DynamicsModel | None = None
    on_subtask: Callable[[str], None] | None = None
    records: list[SubtaskRecord] = field(default_factory=list)
    keep_going: bool = False

    def __post_init__(self) -> None:
        self._loop = ClosedLoopController(self.robot, self.perceiver, self.rng, self.config)

    def execute(self, request: Any) -> ExecutionResult:
        """Run one ``execute`` request in closed loop; raise if it does not reach its target."""
        if self.on_subtask is not None:
            self.on_subtask(request.subtask)
        self._loop.on_replan = self.on_replan
        self._loop.push_model = self.push_model
        name = str(request.movable()["name"])

        def movable() -> Any:  # the entity as currently observed, in world coordinates
            return self.perceiver.detect(name)

        result = self._loop(movable, **request.maps)
        record = SubtaskRecord(request.subtask, result)
        record.picture = self._picture(len(self.records), request.subtask, result)
        self.records.append(record)
        if not result.success and not self.keep_going:
            raise ExecutionFailedError(request.subtask, result.reason, result.message)
        return result

    def reset_to_default_pose(self) -> None:
        """Move the robot back to its rest pose."""
        self.robot.reset_to_default_pose()

    def _picture(self, index: int, subtask: str, result: ExecutionResult) -> Path | None:
        if self.picture_dir is None or result.first_plan is None:
            return None
        from voxposer.planning.picture import plan_figure, write_plan_html

        points = self.perceiver.point_cloud().points
        executed = {"executed (end effector)": np.asarray(result.trace)} if result.trace else {}
        if len(result.entity_path) > 1 and not executed:
            executed = {f"executed ({result.entity})": result.entity_path}
        figure = plan_figure(
            result.first_plan,
            points,
            executed,
            title=f"sub-task {index + 1}: {subtask} ({result.reason})",
        )
        path = write_plan_html(self.picture_dir / f"subtask_{index + 1:02d}.html", figure)
        log.info("wrote %s", path)
        return path
