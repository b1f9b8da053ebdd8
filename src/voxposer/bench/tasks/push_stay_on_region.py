"""Task "push the [obj] while letting it stay on [region]" (Object Interactions).

Success: the block moves at least ``push_min_displacement_m``, never leaves the region (every
trace sample) and ends resting on the table. A correct program pushes it parallel to the
region's boundary.

Reset (so that the constraint binds): the block stands inside the region, 3–6 cm from its
boundary. The instruction names no goal, so the constraint-blind control is the push without
the region clause — "push the block to the middle of the table" — which takes it out of the
region within a few centimetres.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import max_displacement, sample_xy
from voxposer.bench.primitives_programs import primitives_program, push_lines, vec
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, one_subtask, segment_clear
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.places import TABLE_MAX, TABLE_MIN, get_place

#: Per region: start box of the block [m] (inside it, 3–6 cm from its boundary), the
#: direction a correct program pushes it (parallel to the boundary) and the fixed coordinate
#: along that direction it pushes it to [m] (a fixed point: maps are re-evaluated every replan,
#: so "12 cm in front of the block" would run away with the block).
START = {"right side of the table": ((-0.30, 0.18), (-0.12, 0.21), "front", 0.0),
         "left side of the table": ((-0.30, -0.21), (-0.12, -0.18), "front", 0.0),
         "front side of the table": ((-0.05, -0.25), (-0.02, -0.05), "right", 0.10),
         "back side of the table": ((-0.37, 0.12), (-0.34, 0.20), "right", 0.34)}
#: Where the constraint-blind control pushes the block: the middle of the reachable table [m].
MIDDLE = (-0.19, 0.0)
STEP = {"front": (1.0, 0.0), "right": (0.0, 1.0)}
#: How far the baseline pushes the block along the region's boundary [m].
PRIM_PUSH_M = 0.12


class PushStayOnRegion(BenchTask):
    name = "push_stay_on_region"
    category = "Object Interactions"
    template = "push the [obj] while letting it stay on [region]"
    paper_row = "push the [obj] while letting it stay on [region]"
    constraint = "a push goal inside the region"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        lo, hi, _, _ = START[attrs["region"]]
        return block_layout({attrs["obj"]: sample_xy(rng, lo, hi)})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        xy = world.object_position(attrs["obj"])[:2]
        step = STEP[START[attrs["region"]][2]]
        along = [(tuple(xy + np.asarray(step) * d), 0.09) for d in (0.0, 0.06, 0.12, 0.18)]
        return along + segment_clear((float(xy[0]), float(xy[1])), MIDDLE, 0.07)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        path = trace.objects[attrs["obj"]]
        margin = float(np.min(get_place(attrs["region"]).margin(path[:, :2], 0.0)))
        moved = max_displacement(trace, attrs["obj"])
        z = float(path[-1, 2])
        ok = margin >= 0 and moved >= tol.push_min_displacement_m and z <= tol.rest_height_m
        return Verdict(ok, f"moved {moved * 100:.1f} cm, closest {margin * 100:.1f} cm inside the "
                       f"{attrs['region']}", {"moved": moved, "min_margin": margin})

    def reference(self, attrs: dict[str, str]) -> Programs:
        obj, place = attrs["obj"], get_place(attrs["region"])
        _, _, word, goal = START[place.name]
        axis = 0 if word == "front" else 1
        frac = round((goal - TABLE_MIN[axis]) / (TABLE_MAX[axis] - TABLE_MIN[axis]), 3)
        subtask = f"push the {obj} to the {word} while keeping it on the {place.name}"
        query = f"a point {frac:g} of the way across the table toward the {word}, in line with " \
                f"the {obj}"
        progs = one_subtask(Programs(), self.instruction(attrs), subtask, reset=True)
        progs.add("composer", subtask, f"movable = parse_query_obj('{obj}')",
                  f"affordance_map = get_affordance_map('{query}')",
                  "execute(movable, affordance_map=affordance_map)")
        coord = "x" if axis == 0 else "y"
        return progs.add("get_affordance_map", query,
                         "affordance_map = get_empty_affordance_map()",
                         f"block = parse_query_obj('{obj}')", "x, y, z = block.position",
                         "table = parse_query_obj('table')", "lo, hi = table.aabb",
                         f"{coord} = int(round(lo[{axis}] + {frac} * (hi[{axis}] - lo[{axis}])))",
                         "affordance_map[x, y, z] = 1", "ret_val = affordance_map")

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        obj, word = attrs["obj"], START[attrs["region"]][2]
        step = vec(*(PRIM_PUSH_M * c for c in STEP[word]))
        return primitives_program(self.instruction(attrs), [
            f"start = detect('{obj}').position[:2]",
            *push_lines(obj, [f"start + {step}"])])

    def blind(self, attrs: dict[str, str]) -> Programs:
        obj = attrs["obj"]
        subtask = f"push the {obj} to the middle of the table"
        query = f"the middle of the table at the height of the {obj}"
        fx, fy = ((MIDDLE[k] - TABLE_MIN[k]) / (TABLE_MAX[k] - TABLE_MIN[k]) for k in (0, 1))
        progs = one_subtask(Programs(), self.instruction(attrs), subtask, reset=True)
        progs.add("composer", subtask, f"movable = parse_query_obj('{obj}')",
                  f"affordance_map = get_affordance_map('{query}')",
                  "execute(movable, affordance_map=affordance_map)")
        return progs.add("get_affordance_map", query,
                         "affordance_map = get_empty_affordance_map()",
                         f"block = parse_query_obj('{obj}')", "z = block.position[2]",
                         "table = parse_query_obj('table')", "lo, hi = table.aabb",
                         f"x = int(round(lo[0] + {fx:.3f} * (hi[0] - lo[0])))",
                         f"y = int(round(lo[1] + {fy:.3f} * (hi[1] - lo[1])))",
                         "affordance_map[x, y, z] = 1", "ret_val = affordance_map")
