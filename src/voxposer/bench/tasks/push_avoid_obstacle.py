"""Task "push the [obj] to the [pos] while staying away from [obstacle]" (Object Interactions).

[obstacle] takes its values from the block list (App. A.5 gives no separate list). Reset: as
"push the [obj] to the [pos]", with the obstacle block on the straight push, its centre at most
2 cm off the middle of it (``OBSTACLE_OFFSET_M``). Success: the block ends at the place, its
centre stays at least ``obstacle_clearance_m`` (9 cm, 4 cm between the faces) from the
obstacle's centre the whole time, and the obstacle moves at most ``moved_max_m``.

Binds (measured on dev seeds 0–7, both splits): a push that ignores the obstacle goes around it
by the object planner's collision margin alone and keeps 7.4–8.6 cm from it; the reference,
whose 10 cm avoidance map's core the planner keeps out of, keeps 9.7–14.4 cm.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import block_at_place, max_displacement
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, one_subtask, segment_clear, toward
from voxposer.bench.tasks.push_to_pos import push_programs, push_start
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.places import get_place

#: how far the obstacle's centre sits off the middle of the straight push [m].
OBSTACLE_OFFSET_M = (0.0, 0.02)


class PushAvoidObstacle(BenchTask):
    name = "push_to_pos_avoid_obstacle"
    category = "Object Interactions"
    template = "push the [obj] to the [pos] while staying away from [obstacle]"
    paper_row = "push the [obj] to the [pos] while staying away from [obstacle]"

    def instruction(self, attrs: dict[str, str]) -> str:
        return super().instruction(attrs).replace("away from ", "away from the ")

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        target = get_place(attrs["pos"]).point
        start = push_start(rng, get_place(attrs["pos"]), Tolerances())
        half = 0.5 * float(np.hypot(target[0] - start[0], target[1] - start[1]))
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
