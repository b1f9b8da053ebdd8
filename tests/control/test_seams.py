"""The seams hold: the executor and the programs run with a robot that is not the MuJoCo world
(a kinematic test double that follows poses exactly) and a perceiver fed from an observation
saved to disk — no simulator in the loop."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from numpy.typing import ArrayLike, NDArray

from voxposer.control import ClosedLoopController, ExecutorConfig
from voxposer.envs import SceneLayout, TabletopWorld, WorldConfig
from voxposer.errors import ExecutionFailedError, LMPFailedError
from voxposer.lmp.backends.replay import ReplayBackend
from voxposer.perception import SegmentationPerceiver
from voxposer.perception.recorded import RecordedObservations, load_observation, save_observation
from voxposer.pipeline import Embodiment, voxposer_runtime
from voxposer.robot import MoveResult, Robot, StepResult
from voxposer.valuemaps import TOP_DOWN_QUAT, ValueMapAPI

RECORDINGS = Path(__file__).parent / "recordings" / "tabletop.jsonl"
MOVE_ABOVE_BLUE = "move to the top of the blue block while staying away from the green block"
START = (-0.24, -0.30, 0.06)  # low, so the straight way to above the blue block grazes the green


class KinematicRobot:
    """A test double of :class:`voxposer.robot.Robot`: the hand moves at 0.25 m/s (times the
    speed scale) straight toward each commanded position and can never enter y > ``wall_y``."""

    control_period = 0.02
    ee_speed = 0.25  # [m/s] at speed scale 1

    def __init__(self, start: ArrayLike, wall_y: float = np.inf) -> None:
        self.position = np.asarray(start, dtype=float)
        self.quat = np.asarray(TOP_DOWN_QUAT, dtype=float)
        self.wall_y = wall_y
        self.gripper = 0.0
        self.time = 0.0
        self.base_position = np.array([-0.6, 0.0, 0.0])

    def get_ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return self.position.copy(), self.quat.copy()

    def joint_positions(self) -> NDArray[np.float64]:
        return np.zeros(7)

    def _toward(self, target: NDArray[np.float64], speed_scale: float) -> bool:
        step = 0.25 * speed_scale * self.control_period
        delta = target - self.position
        dist = float(np.linalg.norm(delta))
        nxt = target if dist <= step else self.position + delta * (step / dist)
        nxt[1] = min(nxt[1], self.wall_y)
        self.position = nxt
        self.time += self.control_period
        return dist <= step

    def step(self, position: ArrayLike, quat_xyzw: ArrayLike, gripper: float | None = None,
             speed_scale: float = 1.0) -> StepResult:
        at_goal = self._toward(np.asarray(position, dtype=float), speed_scale)
        self.quat = np.asarray(quat_xyzw, dtype=float)
        self.gripper = self.gripper if gripper is None else float(gripper >= 0.5)
        return StepResult(self.position.copy(), at_goal, self.time)

    def move_to_pose(self, position: ArrayLike, quat_xyzw: ArrayLike | None = None,
                     speed_scale: float = 1.0, gripper: float | None = None,
                     max_detour: float | None = None) -> MoveResult:
        target, start = np.asarray(position, dtype=float), self.time
        while not self._toward(target, speed_scale) and self.time - start < 5.0:
            pass
        miss = float(np.linalg.norm(self.position - target))
        return MoveResult(miss < 0.01, miss, 0.0, self.time - start)

    def get_gripper_state(self) -> float:
        return self.gripper

    def gripper_opening(self) -> float:
        return 0.0 if self.gripper else 0.08

    def open_gripper(self) -> None:
        self.gripper = 0.0

    def close_gripper(self) -> None:
        self.gripper = 1.0

    def reset_to_default_pose(self, speed_scale: float = 1.0) -> MoveResult:
        return self.move_to_pose(START, speed_scale=speed_scale)


@pytest.fixture(scope="module")
def saved(world: TabletopWorld, tmp_path_factory: pytest.TempPathFactory
          ) -> tuple[RecordedObservations, dict[str, NDArray[np.float64]]]:
    """An observation of blue and green blocks saved to disk and loaded back, and where the
    simulator had the blocks."""
    world.reset(np.random.default_rng(0), SceneLayout(
        blocks=("blue", "green"), poses={"blue block": (0.0, -0.1), "green block": (-0.12, -0.2)},
        extra_blocks=(0, 0), extra_lines=(0, 0)))
    path = save_observation(world.observe(), tmp_path_factory.mktemp("obs") / "scene.npz")
    truth = {n: world.object_position(n) for n in ("blue block", "green block")}
    return RecordedObservations(load_observation(path), world.object_names), truth


def _segment_to_point(a: NDArray[np.float64], b: NDArray[np.float64], p: NDArray[np.float64]
                      ) -> float:
    t = np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
    return float(np.linalg.norm(a + t * (b - a) - p))


def test_a_move_and_avoid_instruction_runs_on_a_kinematic_robot(saved) -> None:
    source, truth = saved
    robot = KinematicRobot(START)
    assert isinstance(robot, Robot)
    body = Embodiment(robot, SegmentationPerceiver(source, WorldConfig().grid))
    runtime, handoff = voxposer_runtime(body, ReplayBackend(RECORDINGS), np.random.default_rng(0),
                                        executor_config=ExecutorConfig(max_time_s=20))
    runtime.run(MOVE_ABOVE_BLUE)
    (record,) = handoff.records
    assert record.result.success, record.result.message
    target = truth["blue block"] + [0, 0, 0.08 + 0.025]
    assert np.linalg.norm(robot.position - target) < 0.03
    green = truth["green block"]
    # the straight way would pass within 8 cm of the green block; the executed one does not
    assert _segment_to_point(np.array(START), target, green) < 0.075
    assert np.linalg.norm(np.asarray(record.result.trace) - green, axis=1).min() > 0.08


def test_a_move_the_robot_cannot_complete_is_a_failed_subtask_with_a_reason(saved) -> None:
    source, _ = saved
    robot = KinematicRobot(START, wall_y=-0.2)  # the blue block lies beyond the wall
    body = Embodiment(robot, SegmentationPerceiver(source, WorldConfig().grid))
    runtime, handoff = voxposer_runtime(body, ReplayBackend(RECORDINGS), np.random.default_rng(0),
                                        executor_config=ExecutorConfig(max_time_s=20))
    with pytest.raises(LMPFailedError) as info:
        runtime.run(MOVE_ABOVE_BLUE)
    cause: BaseException | None = info.value
    while cause is not None and not isinstance(cause, ExecutionFailedError):
        cause = cause.__cause__
    assert isinstance(cause, ExecutionFailedError)  # planner → composer → the sub-task
    (record,) = handoff.records
    assert not record.result.success and record.result.reason in ("stalled", "timeout")
    assert "cm from the target" in record.result.message
    assert f"failed ({record.result.reason})" in str(info.value)
    (event,) = [e for e in runtime.transcript.events if e["event"] == "execute"]
    assert event["success"] is False and "cm from the target" in event["message"]
    assert robot.position[1] <= -0.2 + 1e-9


def test_pushes_that_end_short_are_counted_in_the_result(saved) -> None:
    source, truth = saved
    robot = KinematicRobot((0.0, -0.35, 0.10), wall_y=-0.16)  # pushes toward +y stop short
    perceiver = SegmentationPerceiver(source, WorldConfig().grid)
    api = ValueMapAPI(perceiver.grid, lambda: robot.quat, robot.get_gripper_state)
    goal = truth["blue block"] + [0.0, 0.15, 0.0]

    def affordance() -> NDArray[np.float32]:
        m = api.get_empty_affordance_map()
        m[tuple(perceiver.grid.world_to_voxel(goal))] = 1
        return m

    result = ClosedLoopController(robot, perceiver, np.random.default_rng(0),
                                  ExecutorConfig(max_time_s=10, max_pushes=3))(
        lambda: perceiver.detect("blue block"), affordance)
    assert not result.success  # the saved scene never changes: the block cannot arrive
    assert result.missed_moves > 0 and result.worst_miss_m > 0.01
    assert "ended away from their targets" in result.message
