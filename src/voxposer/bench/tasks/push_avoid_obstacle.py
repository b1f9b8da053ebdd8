"""Task "push the [obj] to the [pos] while staying away from [obstacle]" (Object Interactions).

[obstacle] takes its values from the block list (App. A.5 gives no separate list). Reset: as
"push the [obj] to the [pos]", with the obstacle block on the straight push, its centre at most
2 cm off the middle of it (``OBSTACLE_OFFSET_M``); the push is long enough that the block starts
and ends at least ``START_CLEAR_M`` beyond the clearance from the obstacle (a start 9.2–9.7 cm
from it, when the check asks 9, left the check bound by where the block stood, not by the path
around: dev seeds 19 UA and 9 SA passed it at 8.7–8.9 cm with correct perception). Success: the
block ends at the place, its centre stays at least ``obstacle_clearance_m`` (9 cm, 4 cm between
the faces) from the obstacle's centre the whole time, and the obstacle moves at most
``moved_max_m``.

Binds (measured on dev seeds 0–7, both splits): a push that ignores the obstacle goes around it
by the object planner's collision margin alone and keeps 7.4–8.6 cm from it; the reference,
whose 10 cm avoidance map's core the planner keeps out of, keeps 9.7–14.4 cm.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import BASE_XY, block_at_place, max_displacement
from voxposer.bench.primitives_programs import (
    PUSH_BACK_M,
    primitives_program,
    push_goal,
    push_lines,
    vec,
)
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, one_subtask, segment_clear, toward
from voxposer.bench.tasks.push_to_pos import push_programs, push_start
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.errors import LayoutError
from voxposer.places import Place, get_place

#: how far the obstacle's centre sits off the middle of the straight push [m].
OBSTACLE_OFFSET_M = (0.0, 0.02)
#: The block starts (and its place lies) at least this far [m] beyond
#: ``Tolerances.obstacle_clearance_m`` from the obstacle's centre.
START_CLEAR_M = 0.03
#: The baseline's detour: the block is pushed sideways this far off the straight push, along it
#: past the obstacle, and back onto the place [m]; on the side whose waypoints lie farther
#: inside this range of distances from the robot's base [m] (the hand reaches the table there).
DETOUR_M = 0.14
REACH_M = (0.36, 0.68)
#: Where the baseline leaves a block pushed to a corner: this far beside its point, away from
#: the obstacle [m] (inside the corner's radius).
CORNER_OFFSET_M = 0.04


class PushAvoidObstacle(BenchTask):
    name = "push_to_pos_avoid_obstacle"
    category = "Object Interactions"
    template = "push the [obj] to the [pos] while staying away from [obstacle]"
    paper_row = "push the [obj] to the [pos] while staying away from [obstacle]"

    def instruction(self, attrs: dict[str, str]) -> str:
        return super().instruction(attrs).replace("away from ", "away from the ")

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        place = get_place(attrs["pos"])
        target = place.point
        tol = Tolerances()
        shortest = 2 * (tol.obstacle_clearance_m + START_CLEAR_M)  # the obstacle halfway
        start = push_start(rng, place, tol, min_length_m=shortest)
        half = 0.5 * float(np.hypot(target[0] - start[0], target[1] - start[1]))
        if 2 * half < shortest:  # the sampler's fallback (its box's centre): draw again
            raise LayoutError(f"a push of {2 * half:.2f} m to the {attrs['pos']}; staying away "
                              f"needs at least {shortest:.2f} m")
        side = 1.0 if rng.uniform() < 0.5 else -1.0
        obstacle = toward(start, target, half, side * float(rng.uniform(*OBSTACLE_OFFSET_M)))
        return block_layout({attrs["obj"]: start, attrs["obstacle"]: obstacle})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        start = tuple(world.object_position(attrs["obj"])[:2])
        return segment_clear(start, get_place(attrs["pos"]).point, 0.12)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        pos = world.object_position(attrs["obj"])
        ok, why = block_at_place(pos, get_place(attrs["pos"]), tol)
        gap = np.linalg.norm(trace.objects[attrs["obj"]][:, :2]
                             - trace.objects[attrs["obstacle"]][:, :2], axis=1)
        closest = float(np.min(gap))
        moved = max_displacement(trace, attrs["obstacle"])
        ok = ok and closest >= tol.obstacle_clearance_m and moved <= tol.moved_max_m
        return Verdict(ok, f"{why}; closest {closest * 100:.1f} cm to the {attrs['obstacle']}, "
                       f"which moved {moved * 100:.1f} cm",
                       {"closest": closest, "obstacle_moved": moved})

    constraint = "avoidance map"

    def reference(self, attrs: dict[str, str], *, blind: bool = False) -> Programs:
        obj, place, obstacle = attrs["obj"], get_place(attrs["pos"]), attrs["obstacle"]
        subtask = f"push the {obj} to the {place.name} while staying away from the {obstacle}"
        progs = one_subtask(Programs(), self.instruction(attrs), subtask, reset=True)
        return push_programs(progs, obj, place, avoid=obstacle, blind=blind)

    def blind(self, attrs: dict[str, str]) -> Programs:
        return self.reference(attrs, blind=True)

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        obj, place = attrs["obj"], get_place(attrs["pos"])
        return primitives_program(self.instruction(attrs), [
            f"block = detect('{obj}')", f"obstacle = detect('{attrs['obstacle']}')",
            f"goal = {push_goal(place)}",
            "d = goal - block.position[:2]",
            "n = np.array([-d[1], d[0]]) / np.linalg.norm(d)",
            # the obstacle stands on the straight push: go round it, DETOUR_M off the line, on
            # the side whose waypoints (and where the hand starts the first push) stay farther
            # inside the arm's reach from its base
            f"base = {vec(*BASE_XY)}",
            f"r = [np.linalg.norm(p - base) for s in (1, -1) for p in (block.position[:2] + s "
            f"* {DETOUR_M} * n, goal + s * {DETOUR_M} * n, block.position[:2] - s * "
            f"{PUSH_BACK_M} * n)]",
            f"inside = [min(d - {REACH_M[0]}, {REACH_M[1]} - d) for d in r]",
            "if min(inside[:3]) < min(inside[3:]):",
            "    n = -n",
            *_last_goal(place),
            *push_lines(obj, [f"block.position[:2] + {DETOUR_M} * n", f"goal + {DETOUR_M} * n",
                              "last"])])


def _last_goal(place: Place) -> list[str]:
    """Baseline code setting ``last``, where the detour leaves the block: a corner's goal
    ``CORNER_OFFSET_M`` beside it (away from the obstacle); for a side, where the detour ends,
    no shallower in the side than its goal."""
    if place.kind == "corner":
        return [f"last = goal + {CORNER_OFFSET_M} * n"]
    k, deeper = place.axis, "max" if place.sign > 0 else "min"
    return [f"last = goal + {DETOUR_M} * n", f"last[{k}] = {deeper}(last[{k}], goal[{k}])"]
