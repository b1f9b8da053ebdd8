"""Closed-loop execution when the entity is an object or a part: plan its path, push, repeat.

Each step observes the scene, re-evaluates the entity and the maps, plans the object's path
(its own points are not obstacles; the table is not one either, it slides on it), chooses a push
by random-shooting MPC (:func:`voxposer.planning.pushing.random_shooting`) and executes the
pushing primitive. It stops when the object reaches the target, when a sliding part (a drawer)
no longer moves although pushed toward the target (the end of its travel: a drawer closed
"as far as it goes"), when pushes stop making progress, or at the time limit.
"""

from __future__ import annotations

import logging
import time
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from voxposer.control.scene_occupancy import scene_occupancy
from voxposer.errors import PlanningError, UnreachablePoseError
from voxposer.planning.pushing import PushAction, push_waypoints, random_shooting
from voxposer.valuemaps.maps import pointat2quat

if TYPE_CHECKING:
    from voxposer.control.executor import ClosedLoopExecutor, ExecutionResult, MapSource

log = logging.getLogger(__name__)

#: Consecutive pushes without progress before a free object counts as stalled.
STALLED_PUSHES = 3
#: Consecutive pushes that did not move a sliding part before it counts as at its end of travel.
END_OF_TRAVEL_PUSHES = 2


def _evaluate(source: Any) -> Any:
    return source() if callable(source) else source


def run_object(
    loop: ClosedLoopExecutor, movable: Any, name: str, maps: dict[str, MapSource]
) -> ExecutionResult:
    """Push ``movable`` (re-detected every step) to the affordance target."""
    cfg, world = loop.config, loop.world
    result = loop.start(name)
    axis_of = getattr(world, "sliding_axis", None)
    axis = axis_of(name) if callable(axis_of) else None
    previous: NDArray[np.float64] | None = None
    stuck = 0
    for _ in range(cfg.max_pushes):
        t0 = time.perf_counter()
        obs = world.observe(rgb=False)
        entity = _evaluate(movable)
        t1 = time.perf_counter()
        values = {k: _evaluate(v) for k, v in maps.items()}
        t2 = time.perf_counter()
        centre = np.asarray(entity["position"], dtype=np.float64)
        try:
            plan = loop.object_planner.plan(
                values["affordance_map"],
                centre,
                avoidance_map=values["avoidance_map"],
                occupancy=scene_occupancy(
                    obs, world.grid, entity=name, holding=False, ignore_table=True
                ),
                entity_occupancy=entity["occupancy"],
            )
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
        if previous is not None:
            moved = float((centre - previous) @ (offset / max(dist, 1e-9)))
            stuck = stuck + 1 if moved < cfg.min_progress_m else 0
            if axis is not None and stuck >= END_OF_TRAVEL_PUSHES:
                return loop.finish(
                    result,
                    "end_of_travel",
                    f"{name} moved as far as it goes "
                    f"toward the target ({dist * 100:.1f} cm short of it)",
                )
            if stuck >= STALLED_PUSHES:
                return loop.finish(
                    result,
                    "stalled",
                    f"pushing {name} made no progress; {dist * 100:.1f} cm from the target",
                )
        action = random_shooting(
            entity["points"],
            plan.trajectory.positions,
            loop.rng,
            cost_map=plan.cost_map,
            axis=axis,
            config=cfg.push,
        )
        if axis is not None:  # a part: push at its centre height, no farther than needed
            action = action._replace(
                contact=np.array([*action.contact[:2], centre[2]]),
                distance=min(action.distance, dist + 0.005),
            )
        previous = centre
        try:
            push(world, action, sideways=axis is not None)
        except UnreachablePoseError as err:
            log.info("push unreachable (%s); sampling another", err)
        if loop.timed_out(result):
            return loop.finish(
                result,
                "timeout",
                f"time limit {cfg.max_time_s:.0f} s reached {dist * 100:.1f} cm from the target",
            )
    return loop.finish(
        result, "stalled", f"{cfg.max_pushes} pushes did not bring {name} to the target"
    )


def push(world: Any, action: PushAction, sideways: bool) -> None:
    """The pushing primitive: above → behind the contact → through → back → up.

    Objects are pushed with the hand pointing down; parts (drawers) with the hand pointing along
    the push, so the forearm stays clear of the cabinet. The gripper is closed first.
    """
    quat = pointat2quat(action.direction if sideways else [0.0, 0.0, -1.0])
    world.close_gripper()
    for k, point in enumerate(push_waypoints(action)):
        world.move_to_pose(point, quat, speed_scale=0.5 if k == 2 else 1.0)
