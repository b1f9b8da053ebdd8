"""Task "push the [obj] to the [pos]" (Object Interactions).

Success: the block ends resting on the table at the place (a corner within ``corner_radius_m``
of its point, or inside a side). Reset: the block starts at least 10 cm outside the place, at most
40 cm from its point, with the push path clear of distractors.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import block_at_place, sample_xy
from voxposer.bench.primitives_programs import primitives_program, push_goal, push_lines
from voxposer.bench.programs import Programs, affordance_place_for_block
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, one_subtask, segment_clear
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.places import Place, get_place

#: Start of a pushed block: inside this box [m], this far outside the place, this close to it.
START_LO, START_HI = (-0.32, -0.28), (0.06, 0.28)
START_OUTSIDE_M = 0.10
START_WITHIN_M = 0.40


def push_start(rng: np.random.Generator, place: Place, tol: Tolerances,
               min_length_m: float = 0.0) -> tuple[float, float]:
    """A start (x, y) [m] for a block to be pushed to ``place``, at least ``min_length_m`` [m]
    from its point."""
    def ok(xy: np.ndarray) -> bool:
        length = np.hypot(*(xy - np.asarray(place.point)))
        return bool(place.margin(xy, tol.corner_radius_m) <= -START_OUTSIDE_M
                    and min_length_m <= length <= START_WITHIN_M)
    return sample_xy(rng, START_LO, START_HI, ok)


def push_programs(progs: Programs, obj: str, place: Place, avoid: str | None = None,
                  *, blind: bool = False) -> Programs:
    """Composer + map programs pushing ``obj`` to ``place`` (avoiding block ``avoid``; with
    ``blind`` the sub-task still names ``avoid`` but no avoidance map is built)."""
    subtask = f"push the {obj} to the {place.name}" + (
        f" while staying away from the {avoid}" if avoid else "")
    if blind:
        avoid = None
    query = f"the {place.name} at the height of the {obj}"
    lines = [f"movable = parse_query_obj('{obj}')",
             f"affordance_map = get_affordance_map('{query}')"]
    if avoid:
        lines.append(f"avoidance_map = get_avoidance_map('10cm around the {avoid}')")
        progs.add("get_avoidance_map", f"10cm around the {avoid}",
                  "avoidance_map = get_empty_avoidance_map()",
                  f"obstacle = parse_query_obj('{avoid}')",
                  "set_voxel_by_radius(avoidance_map, obstacle.position, 10, 1)",
                  "ret_val = avoidance_map")
        lines.append("execute(movable, affordance_map=affordance_map, avoidance_map=avoidance_map)")
    else:
        lines.append("execute(movable, affordance_map=affordance_map)")
    progs.add("composer", subtask, *lines)
    return progs.add("get_affordance_map", query, *affordance_place_for_block(place, obj))


class PushToPos(BenchTask):
    name = "push_to_pos"
    category = "Object Interactions"
    template = "push the [obj] to the [pos]"
    paper_row = "push the [obj] to the [pos]"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        return block_layout({attrs["obj"]: push_start(rng, get_place(attrs["pos"]), Tolerances())})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        start = tuple(world.object_position(attrs["obj"])[:2])
        return segment_clear(start, get_place(attrs["pos"]).point, 0.10)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        pos = world.object_position(attrs["obj"])
        ok, why = block_at_place(pos, get_place(attrs["pos"]), tol)
        return Verdict(ok, why, {"x": float(pos[0]), "y": float(pos[1])})

    def reference(self, attrs: dict[str, str]) -> Programs:
        obj, place = attrs["obj"], get_place(attrs["pos"])
        progs = one_subtask(Programs(), self.instruction(attrs),
                            f"push the {obj} to the {place.name}", reset=True)
        return push_programs(progs, obj, place)

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        return primitives_program(self.instruction(attrs),
                                  push_lines(attrs["obj"], [push_goal(get_place(attrs["pos"]))]))
