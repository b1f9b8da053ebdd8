"""``execute(movable, affordance_map, …)``: closed-loop execution of composed value maps.

Paper Sec. 3.3 and App. A.3. The entity of interest and every value map are callables
re-evaluated at every replanning step against the latest observation (the cached LLM programs run
again; no new LLM call). The loop: observe → recompose maps → plan → follow the trajectory for
one replanning period → repeat, until the entity reaches the affordance target, progress stalls
or the time limit passes — and the result says which.

When the entity is the end effector the trajectory is followed through the robot's pose
controller with the velocity scale, orientation and gripper command read from the maps. When it
is an object or a part (a drawer, a handle), the planner plans the object's path and
random-shooting MPC over a planar pushing model chooses each push
(:mod:`voxposer.planning.mpc`), executed by a pushing primitive — unless the object is in
the closed hand (its detected centre within ``ExecutorConfig.carry_radius_m`` of the end
effector): then it moves with the hand (paper App. A.3), so the hand's path is planned for the
object's centre and followed with the grasp offset subtracted.

An affordance that moves with the entity itself is anchored where it was first computed
(:mod:`voxposer.control.anchoring`), except for a sliding part (a drawer), which is pushed until
its end of travel.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from voxposer.control.anchoring import SelfRelativeAnchor
from voxposer.control.config import ExecutorConfig
from voxposer.control.execution_result import ExecutionResult, MapSource, StopReason, evaluate
from voxposer.control.pushing_loop import run_object
from voxposer.control.tracking import follow
from voxposer.errors import PlanningError, VoxPoserError
from voxposer.perception.names import is_end_effector
from voxposer.perception.perceiver import Perceiver
from voxposer.planning.dynamics import DynamicsModel
from voxposer.planning.planner import PathPlanner, Plan
from voxposer.robot import Robot

log = logging.getLogger(__name__)

def _raise_to(grid: Any, affordance: NDArray[Any], min_z: float) -> NDArray[Any]:
    """``affordance`` with every target voxel below height ``min_z`` [m] moved up to it."""
    kz = int(np.clip(grid.world_to_voxel([0.0, 0.0, min_z], clip=True)[2], 0, grid.shape[2] - 1))
    low = np.asarray(affordance)[:, :, :kz]
    if kz == 0 or not low.any():
        return affordance
    out = np.array(affordance, copy=True)
    out[:, :, kz] = np.maximum(out[:, :, kz], low.max(axis=2))
    out[:, :, :kz] = 0
    return out


class ClosedLoopController:
    """Runs ``execute`` with a robot and a perceiver; reusable across calls.

    Args:
        robot: the arm (:class:`voxposer.robot.Robot`; the MuJoCo world is one).
        perceiver: observations, detection and obstacles
            (:class:`voxposer.perception.perceiver.Perceiver`).
        rng: randomness of the pushing MPC.
        config: closed-loop parameters.
    """

    def __init__(
        self, robot: Robot, perceiver: Perceiver, rng: np.random.Generator,
        config: ExecutorConfig | None = None,
    ) -> None:
        self.robot = robot
        self.perceiver = perceiver
        self.grid = perceiver.grid
        self.rng = rng
        self.config = config or ExecutorConfig()
        self.ee_planner = PathPlanner(self.grid, self.config.ee_planner)
        self.object_planner = PathPlanner(self.grid, self.config.object_planner)
        self.history: list[ExecutionResult] = []
        #: called after every replan with (result so far, plan); for live progress displays
        self.on_replan: Callable[[ExecutionResult, Plan], None] | None = None
        #: the push dynamics model the pushing MPC samples through (None: the paper's
        #: heuristic, :class:`~voxposer.planning.dynamics.TranslationPush`)
        self.push_model: DynamicsModel | None = None

    def __call__(
        self,
        movable: Any,
        affordance_map: MapSource = None,
        avoidance_map: MapSource = None,
        rotation_map: MapSource = None,
        velocity_map: MapSource = None,
        gripper_map: MapSource = None,
    ) -> ExecutionResult:
        """Execute until the entity reaches the affordance target (see module docs).

        Args:
            movable: the entity — a detected object, or a callable returning one
                (``detect("gripper")`` for the end effector).
            affordance_map … gripper_map: arrays or callables returning arrays on the perceiver's
                grid; None = not specified. The affordance map is required.
        """
        if affordance_map is None:
            raise PlanningError("execute() needs an affordance_map: nothing says where to go")
        entity = evaluate(movable)
        name = str(entity["name"])
        hand = is_end_effector(name)

        def position() -> NDArray[np.float64]:  # the entity's, for anchoring
            if hand:
                return self.robot.get_ee_pose()[0]
            return np.asarray(evaluate(movable)["position"], dtype=np.float64)

        slides = not hand and self.perceiver.sliding_axis(name) is not None
        maps = {
            # a sliding part stops at its end of travel, so a target moving with it is kept
            # ("push the handle 20 cm in" = until the drawer is shut)
            "affordance_map": affordance_map if slides else
            SelfRelativeAnchor(affordance_map, position, self.grid),
            "avoidance_map": avoidance_map,
            "rotation_map": rotation_map,
            "velocity_map": velocity_map,
            "gripper_map": gripper_map,
        }
        if hand:
            result = self._run_end_effector(name, maps)
        elif self._carry_offset(entity) is not None:
            result = self._run_end_effector(name, maps, movable)
        else:
            result = self._run_object(movable, name, maps)
        self.history.append(result)
        return result

    def _carry_offset(self, entity: Any) -> NDArray[np.float64] | None:
        """Object centre − end effector [m], shape (3,), when ``entity`` is in the closed hand
        (closed on something: fingers at least ``carry_min_opening_m`` apart — after a push the
        hand is closed on nothing next to the block it pushed)."""
        if self.robot.get_gripper_state() < 0.5:
            return None
        if float(self.robot.gripper_opening()) < self.config.carry_min_opening_m:
            return None
        offset = np.asarray(entity["position"], dtype=np.float64) - self.robot.get_ee_pose()[0]
        return offset if float(np.linalg.norm(offset)) <= self.config.carry_radius_m else None

    # ----------------------------------------------------------- end effector
    def _run_end_effector(
        self, name: str, maps: dict[str, MapSource], carried: Any = None
    ) -> ExecutionResult:
        """Move the hand. With ``carried`` (an object in the hand, or a callable re-detecting
        it) the plan is for that object's centre, the hand follows it shifted back by the
        measured grasp offset, and a target lower than the object can rest is raised to its
        resting height (an object cannot be carried into the table)."""
        shift = np.zeros(3)
        rest_z = -np.inf
        if carried is not None:
            held = evaluate(carried)
            rest_z = float(held["position"][2] - np.asarray(held["aabb"])[0][2])
        floor_z = self._hand_floor() if carried is None else None
        cfg, robot = self.config, self.robot
        control_dt = float(robot.control_period)
        steps_per_replan = max(1, round(1.0 / cfg.replan_hz / control_dt))
        result = self.start(name)
        best, since_best = float("inf"), 0
        while True:
            t0 = time.perf_counter()
            self.perceiver.point_cloud()  # observe and fuse (timed as "observe")
            t1 = time.perf_counter()
            values = {k: evaluate(v) for k, v in maps.items()}
            hand_pos, ee_quat = robot.get_ee_pose()
            if carried is not None:
                measured = self._carry_offset(evaluate(carried))
                if measured is None and robot.get_gripper_state() < 0.5:
                    return self.finish(result, "reached", f"{name} released: the gripper map "
                                       "opened the hand")
                if measured is None:
                    return self.finish(result, "stalled", f"{name} slipped out of the hand")
                shift = measured
                values["affordance_map"] = _raise_to(self.grid, values["affordance_map"], rest_z)
            elif floor_z is not None:
                values["affordance_map"] = _raise_to(self.grid, values["affordance_map"], floor_z)
            t2 = time.perf_counter()
            ee_pos = hand_pos + shift
            holding = robot.get_gripper_state() >= 0.5
            try:
                plan = self.ee_planner.plan(
                    values["affordance_map"],
                    ee_pos,
                    avoidance_map=values["avoidance_map"],
                    rotation_map=values["rotation_map"],
                    velocity_map=values["velocity_map"],
                    gripper_map=values["gripper_map"],
                    occupancy=self.perceiver.scene_occupancy(name, holding=holding),
                    current_quat=ee_quat,
                    current_gripper=robot.get_gripper_state(),
                )
            except PlanningError as err:
                return self.finish(result, "planning_failed", str(err))
            dist = float(np.linalg.norm(ee_pos - plan.target))
            self.record(result, plan, ee_pos, dist, (t0, t1, t2))
            if dist <= cfg.reach_tolerance_m:
                self._finish_gripper(plan)
                return self.finish(
                    result, "reached", f"{name} reached the target ({dist * 100:.1f} cm away)"
                )
            best, since_best = (
                (dist, 0) if dist < best - cfg.min_progress_m else (best, since_best + 1)
            )
            if since_best >= cfg.stall_replans:
                return self.finish(
                    result,
                    "stalled",
                    f"{name} stopped making progress "
                    f"{dist * 100:.1f} cm from the target (blocked or unreachable?)",
                )
            if self.timed_out(result):
                return self.finish(
                    result,
                    "timeout",
                    f"time limit {cfg.max_time_s:.0f} s reached "
                    f"{dist * 100:.1f} cm from the target",
                )
            follow(self.robot, plan.trajectory, steps_per_replan, result, shift,
                   self.config.lookahead_m)

    def _hand_floor(self) -> float | None:
        """The lowest target height of the bare hand [m]: ``hand_floor_m`` above the table's
        top (None when the table is not seen or the floor is off)."""
        if self.config.hand_floor_m <= 0:
            return None
        try:
            table = self.perceiver.detect("table")
        except VoxPoserError:
            return None
        return float(np.asarray(table["aabb"])[1][2]) + self.config.hand_floor_m

    def _finish_gripper(self, plan: Plan) -> None:
        """Apply the gripper command of the target voxel once there (e.g. close to grasp)."""
        want = float(plan.trajectory.gripper[-1])
        if (want >= 0.5) != (self.robot.get_gripper_state() >= 0.5):
            if want >= 0.5:
                self.robot.close_gripper()
            else:
                self.robot.open_gripper()

    # ----------------------------------------------------------------- objects
    def _run_object(self, movable: Any, name: str, maps: dict[str, MapSource]) -> ExecutionResult:
        return run_object(self, movable, name, maps)

    # ------------------------------------------------------------------ common
    def _sim_time(self) -> float:
        return float(self.robot.time)

    def start(self, entity: str) -> ExecutionResult:
        """A fresh result for one ``execute`` call, its clocks started."""
        return ExecutionResult(False, "timeout", "", entity, started_sim=self._sim_time())

    def record(
        self,
        result: ExecutionResult,
        plan: Plan,
        position: NDArray[np.float64],
        distance: float,
        clock: tuple[float, float, float],
    ) -> None:
        """Book-keeping after each plan: timings (observe, maps, plan), plans, the entity's
        position and distance to the target; then the ``on_replan`` callback."""
        t0, t1, t2 = clock
        result.timings_ms.append(
            {
                "observe": (t1 - t0) * 1e3,
                "maps": (t2 - t1) * 1e3,
                "plan": (time.perf_counter() - t2) * 1e3,
            }
        )
        result.replans += 1
        result.last_plan = plan
        result.first_plan = result.first_plan or plan
        result.final_distance = distance
        result._path.append(np.asarray(position, dtype=np.float64))
        if self.on_replan is not None:
            self.on_replan(result, plan)

    def timed_out(self, result: ExecutionResult) -> bool:
        """Whether the call has used its simulated time budget."""
        return self._sim_time() - result.started_sim >= self.config.max_time_s

    def finish(self, result: ExecutionResult, reason: StopReason, message: str) -> ExecutionResult:
        """Close ``result`` with a stop reason and a sentence saying why."""
        result.success = reason in ("reached", "end_of_travel")
        result.reason = reason
        if result.missed_moves:
            message += (f"; {result.missed_moves} of the robot's moves ended away from their "
                        f"targets (worst by {result.worst_miss_m * 100:.1f} cm)")
        result.message = message
        result.entity_path = np.asarray(result._path).reshape(-1, 3)
        result.wall_time = time.perf_counter() - result.started_wall
        result.sim_time = self._sim_time() - result.started_sim
        log.info("execute(%s): %s — %s", result.entity, reason, message)
        return result


__all__ = ["ClosedLoopController"]
