"""Closed-loop execution when the entity is an object or a part: plan its path, push, repeat.

Each step observes the scene, re-evaluates the entity and the maps, plans the object's path
(its own points are not obstacles; the table is not one either, it slides on it; a sliding
part's joint alone sets its travel, so nothing is an obstacle to it), chooses a push
by random-shooting MPC (:func:`voxposer.planning.mpc.random_shooting`) and executes the
pushing primitive. It stops when the object reaches the target, when a sliding part (a drawer)
no longer moves although pushed toward the target (the end of its travel: a drawer closed
"as far as it goes"), when pushes stop making progress, or at the time limit.
"""

from __future__ import annotations

import logging
import time
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from voxposer.control.execution_result import ExecutionResult, MapSource, StopReason, evaluate
from voxposer.control.table_layer import beyond_push_reach, onto_layer
from voxposer.errors import PlanningError, UnreachablePoseError
from voxposer.geometry.frames import TOP_DOWN_QUAT, pointat2quat
from voxposer.perception.perceiver import Perceiver
from voxposer.planning.dynamics import DynamicsModel
from voxposer.planning.mpc import random_shooting
from voxposer.planning.push_primitive import PushAction, push_waypoints
from voxposer.robot import MoveResult, Robot

log = logging.getLogger(__name__)

#: Consecutive pushes without progress before a free object counts as stalled.
STALLED_PUSHES = 3
#: Consecutive pushes that did not move a sliding part before it counts as at its end of travel.
END_OF_TRAVEL_PUSHES = 2


class LoopHost(Protocol):
    """What the pushing loop uses of the closed-loop controller that runs it."""

    config: Any
    robot: Robot
    perceiver: Perceiver
    object_planner: Any
    rng: np.random.Generator
    push_model: DynamicsModel | None

    def start(self, name: str) -> ExecutionResult: ...
    def finish(self, result: ExecutionResult, reason: StopReason, message: str
               ) -> ExecutionResult: ...
    def record(self, result: ExecutionResult, plan: Any, position: Any, distance: float,
               clock: tuple[float, float, float]) -> None: ...
    def timed_out(self, result: ExecutionResult) -> bool: ...


def run_object(
    loop: LoopHost, movable: Any, name: str, maps: dict[str, MapSource]
) -> ExecutionResult:
    """Push ``movable`` (re-detected every step) to the affordance target."""
    cfg, robot, perceiver = loop.config, loop.robot, loop.perceiver
    result = loop.start(name)
    axis = perceiver.sliding_axis(name)
    previous: NDArray[np.float64] | None = None
    previous_left = 0.0
    stuck = 0
    refused: list[tuple[NDArray[np.float64], NDArray[np.float64]]] = []  # (centre, direction)
    for _ in range(cfg.max_pushes):
        t0 = time.perf_counter()
        perceiver.point_cloud()  # observe and fuse (timed as "observe")
        entity = evaluate(movable)
        t1 = time.perf_counter()
        values = {k: evaluate(v) for k, v in maps.items()}
        t2 = time.perf_counter()
        centre = np.asarray(entity["position"], dtype=np.float64)
        try:
            plan = _plan_object(loop, name, entity, values, sliding=axis is not None)
        except PlanningError as err:
            return loop.finish(result, "planning_failed", str(err))
        offset = plan.target - centre
        offset = offset @ axis * axis if axis is not None else np.array([*offset[:2], 0.0])
        dist = float(np.linalg.norm(offset))
        loop.record(result, plan, centre, dist, (t0, t1, t2))
        if dist <= cfg.reach_tolerance_m:
            return loop.finish(
                result, "reached", f"{name} reached the target ({dist * 100:.1f} cm away)"
            )
        left = _path_left(plan.trajectory.positions)
        if previous is not None:
            # progress of a free object: along its planned path (a detour around what it must
            # avoid first moves it sideways); of a sliding part: along its axis
            moved = (float((centre - previous) @ (offset / max(dist, 1e-9))) if axis is not None
                     else previous_left - left)
            stuck = stuck + 1 if moved < cfg.min_progress_m else 0
            if axis is not None and moved < -cfg.min_progress_m:
                stuck = 0  # a part pulled back (e.g. a drawer reopened) is not at its end
            stop = _stuck_stop(stuck, axis is not None, name, dist)
            if stop is not None:
                return loop.finish(result, *stop)
        action = random_shooting(
            entity["points"],
            plan.trajectory.positions,
            loop.rng,
            cost_map=plan.cost_map,
            axis=axis,
            config=cfg.push,
            model=_model_for(loop.push_model, sliding=axis is not None),
            refused=_refused_here(refused, centre),
        )
        if axis is not None:  # a part: push at its centre height, no farther than needed
            action = action._replace(
                contact=np.array([*action.contact[:2], centre[2]]),
                distance=min(action.distance, dist + 0.005),
            )
        previous, previous_left = centre, left
        try:
            top = float(np.asarray(entity["points"])[:, 2].max())
            _count_misses(result, push(robot, action, sideways=axis is not None, object_top=top))
        except UnreachablePoseError as err:
            # the arm did not move: not a push that failed to make progress (max_pushes caps it)
            log.info("push unreachable (%s); sampling another", err)
            previous = None
            refused.append((centre, np.asarray(action.direction, dtype=np.float64)))
        if loop.timed_out(result):
            return loop.finish(
                result,
                "timeout",
                f"time limit {cfg.max_time_s:.0f} s reached {dist * 100:.1f} cm from the target",
            )
    return loop.finish(
        result, "stalled", f"{cfg.max_pushes} pushes did not bring {name} to the target"
    )


#: a refused push counts while the object is within this distance [m] of where it was refused.
REFUSED_RADIUS_M = 0.02


def _refused_here(refused: list[tuple[NDArray[np.float64], NDArray[np.float64]]],
                  centre: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """The directions (shape (R, 3)) of the pushes the arm could not reach with the object
    within :data:`REFUSED_RADIUS_M` of ``centre`` [m]; None when there are none."""
    here = [d for c, d in refused if np.linalg.norm((c - centre)[:2]) <= REFUSED_RADIUS_M]
    return np.asarray(here) if here else None


def _model_for(model: DynamicsModel | None, *, sliding: bool) -> DynamicsModel | None:
    """``model`` for this push, or None (the heuristic) for a sliding part when the model says
    it knows only free objects (``handles_parts`` False: a model learned on blocks)."""
    if sliding and not getattr(model, "handles_parts", True):
        return None
    return model


def _plan_object(loop: LoopHost, name: str, entity: Any, values: dict[str, Any], *,
                 sliding: bool) -> Any:
    """The object's path from its detected centre to the affordance target (its own points and
    the table are no obstacles); a free object's path stays at its height, its target brought
    there (:mod:`voxposer.control.table_layer`). A sliding part's has no obstacles: what lies
    ahead of a drawer's handle is its own cabinet, and with noisy depth the cabinet's unlabelled
    edge points lie over the handle, turning its path (and the push) away from the target.
    A free object's path keeps within the pushing reach of the robot's base
    (:func:`~voxposer.control.table_layer.beyond_push_reach`) where that leaves a path that
    also keeps out of the avoidance map's core."""
    centre = np.asarray(entity["position"], dtype=np.float64)
    affordance = values["affordance_map"]
    layer = None if sliding else float(centre[2])
    if layer is not None:
        affordance = onto_layer(loop.perceiver.grid, affordance, layer)
    occupancy = None if sliding else loop.perceiver.scene_occupancy(
        name, holding=False, ignore_table=True)

    def plan(off_limits: NDArray[np.bool_] | None) -> Any:
        return loop.object_planner.plan(
            affordance, centre, avoidance_map=values["avoidance_map"], occupancy=occupancy,
            entity_occupancy=entity["occupancy"], layer_z=layer, off_limits=off_limits)

    reach = loop.config.push_reach_m
    if sliding or reach[1] <= 0:
        return plan(None)
    try:  # within the pushing reach where that leaves a path around what is avoided
        kept = plan(beyond_push_reach(loop.perceiver.grid, loop.robot.base_position, reach))
    except PlanningError:
        return plan(None)
    if not getattr(kept, "relaxed", False):
        return kept
    free = plan(None)  # the reach gives way before the avoidance map's core does
    return kept if getattr(free, "relaxed", False) else free


def _path_left(positions: NDArray[np.float64]) -> float:
    """Length [m] of a planned path, shape (N, 3)."""
    return float(np.linalg.norm(np.diff(positions, axis=0), axis=1).sum()) if len(positions) > 1 \
        else 0.0


def _stuck_stop(stuck: int, sliding: bool, name: str, dist: float
                ) -> tuple[StopReason, str] | None:
    """(reason, message) to stop with after ``stuck`` pushes without progress, or None: a sliding
    part is at its end of travel after ``END_OF_TRAVEL_PUSHES``, anything after
    ``STALLED_PUSHES``; ``dist`` is the remaining distance to the target [m]."""
    if sliding and stuck >= END_OF_TRAVEL_PUSHES:
        return ("end_of_travel", f"{name} moved as far as it goes toward the target "
                f"({dist * 100:.1f} cm short of it)")
    if stuck >= STALLED_PUSHES:
        return ("stalled", f"pushing {name} made no progress; {dist * 100:.1f} cm from the target")
    return None


def _count_misses(result: ExecutionResult, moves: list[MoveResult]) -> None:
    """Add the push's moves that ended away from their targets to ``result``."""
    missed = [float(m.position_error) for m in moves if not m.reached]
    result.missed_moves += len(missed)
    result.worst_miss_m = max([result.worst_miss_m, *missed])


#: With the hand top-down, the Panda's wrist joint (joint 7, range ±2.9 rad) sits near the middle
#: of its range when the hand's yaw away from :data:`TOP_DOWN_QUAT` is the arm's azimuth (the
#: direction from the base to the hand) plus this [rad] (joint 7 ≈ 0.785 + azimuth − yaw).
MID_WRIST_YAW = np.pi / 4


def top_down_quat(hand_axis: NDArray[np.float64], azimuth: float = 0.0) -> NDArray[np.float64]:
    """Top-down hand orientation (x, y, z, w) whose finger axis lies along ``hand_axis``.

    ``hand_axis`` is a table-plane direction, shape (3,). The hand is symmetric under a half
    turn about its approach axis; of the two yaws, the one that keeps the wrist joint nearest
    the middle of its range for an arm reaching toward ``azimuth`` [rad] is chosen (yaw 0 =
    :data:`TOP_DOWN_QUAT`, finger axis along world y).
    """
    yaw = float(np.arctan2(hand_axis[1], hand_axis[0])) - np.pi / 2
    centre = azimuth + MID_WRIST_YAW
    yaw = centre + (yaw - centre + np.pi / 2) % np.pi - np.pi / 2
    q = (Rotation.from_euler("z", yaw) * Rotation.from_quat(TOP_DOWN_QUAT)).as_quat()
    return np.asarray(q if q[3] >= 0 else -q, dtype=np.float64)


def side_push_quat(direction: NDArray[np.float64]) -> NDArray[np.float64]:
    """Hand orientation (x, y, z, w) for pushing a part (a drawer's handle) along ``direction``
    (a table-plane direction, shape (3,)): the hand points along the push with its long
    (finger) axis level, across the push. With that axis upright the 21 cm hand stands on the
    table before the hand reaches a bottom drawer's handle (its centre ~10 cm up at best)."""
    return pointat2quat(direction, fingers=np.cross([0.0, 0.0, 1.0], direction))


#: Fingertips below the end-effector point plus a margin: how far above an object's top the
#: end effector travels between pushes [m].
TOP_CLEARANCE_M = 0.033
#: An approach move (above or behind the contact) ending farther than this from its target [m]
#: abandons the push (the arm could not take the pose there, e.g. top-down right in front of
#: its base).
APPROACH_MISS_M = 0.02
#: How far the hand may leave each push move's straight line to finish it where the line
#: gets stuck (in front of the robot's base) [m] (``Robot.move_to_pose(max_detour=...)``):
#: above and behind the contact (no limit: a descent that ends short abandons the push, and
#: limiting it stalls pushes by the base — measured with 3 and 8 cm, and again with 6 cm, which
#: lost 5 of 120 ground-truth staying-away dev episodes to blocks left short), through, back,
#: up. Finishing those last three in joint space swept the hand across the table, into the
#: pushed block or the one to stay away from (measured: 7 of 80 dev episodes moved it with
#: ground truth, 2 with these limits).
PUSH_DETOURS_M: tuple[float | None, ...] = (None, None, 0.03, 0.03, 0.03)


def push(robot: Robot, action: PushAction, sideways: bool, object_top: float | None = None
         ) -> list[MoveResult]:
    """The pushing primitive: above → behind the contact → through → back → up.

    Objects are pushed with the hand pointing down, its long (finger) axis along
    ``action.hand_axis``, and the hand travels between pushes just above the object's top
    (``object_top`` [m]; no higher than needed: right in front of the base the arm cannot hold
    its hand top-down much above 8 cm). Parts (drawers) are pushed with the hand pointing along
    the push, so the forearm stays clear of the cabinet, its fingers level
    (:func:`side_push_quat`). The gripper is closed first.

    A push whose approach (above, then behind the contact) ends more than
    :data:`APPROACH_MISS_M` from its target is abandoned: the hand goes straight up.

    Returns:
        the robot's result of each move made (``reached``, ``position_error`` [m]): five, or
        the approach and the move up of an abandoned push.
    """
    reach = action.contact[:2] - robot.base_position[:2]
    azimuth = float(np.arctan2(reach[1], reach[0]))
    quat = side_push_quat(action.direction) if sideways else top_down_quat(action.hand_axis, azimuth)
    robot.close_gripper()
    lift = {} if sideways or object_top is None else {
        "lift_height_m": max(0.03, object_top + TOP_CLEARANCE_M - float(action.contact[2]))}
    waypoints = push_waypoints(action, **lift)
    moves: list[MoveResult] = []
    for k, point in enumerate(waypoints):
        moves.append(robot.move_to_pose(point, quat, speed_scale=0.5 if k == 2 else 1.0,
                                        max_detour=PUSH_DETOURS_M[k]))
        if k < 2 and moves[-1].position_error > APPROACH_MISS_M:
            # the hand is not behind the contact: pushing "through" from wherever it is would
            # sweep the object sideways; straight up instead, and the loop samples again
            here, _ = robot.get_ee_pose()
            up = np.array([*np.asarray(here)[:2], max(float(here[2]), float(waypoints[0][2]))])
            moves.append(robot.move_to_pose(up, quat, max_detour=PUSH_DETOURS_M[-1]))
            break
    return moves
