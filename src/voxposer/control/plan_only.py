"""Planning without a robot: what ``voxposer run --frames DIR --robot none`` executes through.

:class:`RecordedPoseRobot` is a stub :class:`~voxposer.robot.Robot` that reports the pose recorded
with the frames and refuses every motion (:class:`NoRobotError`). :class:`PlanOnlyHandoff`
implements the LMP runtime's ``ExecuteHandler``: the first ``execute`` call runs the closed-loop
controller up to its first plan — the same plan a live run makes first, from the recorded
end-effector pose — and stops it there, before any motion; the sub-tasks after it are listed but
not planned (the scene they would start from is never observed), and ``reset_to_default_pose``
is not done (the plan starts from the recorded pose). Nothing fails silently: each result says
it was planned only or not planned.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer import tabletop
from voxposer.control.closed_loop import ClosedLoopController
from voxposer.control.config import ExecutorConfig
from voxposer.control.execution_result import ExecutionResult
from voxposer.control.robot_handoff import SubtaskRecord
from voxposer.errors import NoRobotError
from voxposer.perception.observation import Observation
from voxposer.perception.perceiver import Perceiver
from voxposer.planning.planner import Plan
from voxposer.robot import MoveResult, Robot, StepResult

log = logging.getLogger(__name__)

#: What a planned-only sub-task's result message says.
PLANNED_ONLY = "planned only (--robot none): the robot was not moved"


class RecordedPoseRobot:
    """A stub :class:`~voxposer.robot.Robot` that reports the robot state recorded in an
    observation and refuses to move.

    Args:
        observation: gives the end-effector pose [m], (x, y, z, w), the gripper state and time.
        gripper_opening_m: measured finger distance [m]; None: 0.08 open, 0 closed.
        base_position: the arm's base [m], shape (3,) (default: the tabletop's).
    """

    control_period = 0.02  # nominal [s]; nothing is stepped
    ee_speed = 0.25  # nominal [m/s] (the tabletop controller's default); nothing moves

    def __init__(self, observation: Observation, gripper_opening_m: float | None = None,
                 base_position: ArrayLike | None = None) -> None:
        self._obs = observation
        self._opening = gripper_opening_m
        self.base_position = np.asarray(tabletop.ROBOT_BASE if base_position is None
                                        else base_position, dtype=np.float64)

    @property
    def time(self) -> float:
        return float(self._obs.time)

    def get_ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return (np.array(self._obs.ee_position, dtype=np.float64),
                np.array(self._obs.ee_quat, dtype=np.float64))

    def joint_positions(self) -> NDArray[np.float64]:
        return self._refuse("report joint angles (none were recorded)")

    def get_gripper_state(self) -> float:
        return float(self._obs.gripper)

    def gripper_opening(self) -> float:
        if self._opening is not None:
            return float(self._opening)
        return 0.0 if self._obs.gripper >= 0.5 else 0.08

    def step(self, position: ArrayLike, quat_xyzw: ArrayLike, gripper: float | None = None,
             speed_scale: float = 1.0) -> StepResult:
        return self._refuse(f"step toward {np.asarray(position).round(3).tolist()} m")

    def move_to_pose(self, position: ArrayLike, quat_xyzw: ArrayLike | None = None,
                     speed_scale: float = 1.0, gripper: float | None = None,
                     max_detour: float | None = None) -> MoveResult:
        return self._refuse(f"move to {np.asarray(position).round(3).tolist()} m")

    def open_gripper(self) -> None:
        self._refuse("open the gripper")

    def close_gripper(self) -> None:
        self._refuse("close the gripper")

    def reset_to_default_pose(self, speed_scale: float = 1.0) -> MoveResult:
        return self._refuse("move to the rest pose")

    def _refuse(self, what: str) -> NoReturn:
        raise NoRobotError(f"cannot {what}: this is the robot state recorded with the frames, "
                           "not a robot (--robot none)")


class _FirstPlan(Exception):
    """Stops the closed loop at its first plan."""

    def __init__(self, result: ExecutionResult, plan: Plan) -> None:
        super().__init__("first plan made")
        self.result, self.plan = result, plan


@dataclass
class PlanOnlyHandoff:
    """An ``ExecuteHandler`` that plans the first sub-task and moves nothing (module docs).

    Attributes:
        robot: reports the pose to plan from (:class:`RecordedPoseRobot`); never moved.
        perceiver: what detects the entity and the obstacles.
        rng: randomness of the pushing MPC (not reached before the first plan).
        config: closed-loop parameters (planners, anchoring).
        picture_dir: where ``subtask_01.html`` goes (None: none).
        records: the planned sub-task (``result.first_plan``).
        skipped: the sub-tasks after it, not planned.
    """

    robot: Robot
    perceiver: Perceiver
    rng: np.random.Generator
    config: ExecutorConfig = field(default_factory=ExecutorConfig)
    picture_dir: Path | None = None
    records: list[SubtaskRecord] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)

    def execute(self, request: Any) -> ExecutionResult:
        """Plan ``request`` if it is the first sub-task, else list it as skipped."""
        name = str(request.movable()["name"])
        if self.records:
            self.skipped.append(request.subtask)
            log.info("not planned (--robot none): %s", request.subtask)
            return ExecutionResult(False, "timeout", f"not planned: {PLANNED_ONLY}", name)
        loop = ClosedLoopController(self.robot, self.perceiver, self.rng, self.config)

        def stop(result: ExecutionResult, plan: Plan) -> None:
            raise _FirstPlan(result, plan)

        loop.on_replan = stop
        try:
            result = loop(lambda: self.perceiver.detect(name), **request.maps)
        except _FirstPlan as first:
            result = first.result
            result.message = PLANNED_ONLY
            result.entity_path = np.asarray(first.plan.trajectory.positions[:1])
        else:  # stopped before planning (a planning failure): say why
            self.records.append(SubtaskRecord(request.subtask, result))
            return result
        record = SubtaskRecord(request.subtask, result)
        record.picture = self._picture(request.subtask, result)
        self.records.append(record)
        return result

    def reset_to_default_pose(self) -> None:
        """Not done (there is no robot): the plan starts from the recorded pose; listed in
        ``skipped``."""
        self.skipped.append("reset_to_default_pose()")
        log.info("reset_to_default_pose() not done (--robot none): planning from the recorded "
                 "pose")

    def _picture(self, subtask: str, result: ExecutionResult) -> Path | None:
        """``subtask_01.html``: the composed maps and the planned path, as a live run draws
        them (no executed path)."""
        if self.picture_dir is None or result.first_plan is None:
            return None
        from voxposer.planning.picture import plan_figure, write_plan_html

        figure = plan_figure(result.first_plan, self.perceiver.point_cloud().points, {},
                             title=f"sub-task 1: {subtask} (planned only, not executed)")
        path = write_plan_html(self.picture_dir / "subtask_01.html", figure)
        log.info("wrote %s", path)
        return path


__all__ = ["PLANNED_ONLY", "NoRobotError", "PlanOnlyHandoff", "RecordedPoseRobot"]  # re-exported
