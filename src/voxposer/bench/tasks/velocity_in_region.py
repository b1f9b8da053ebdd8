"""Task "move to the [pos] while moving at [velocity] in the [region]" (Spatial Composition).

Success: the end effector ends at the place, and inside the region (a table side, see
:mod:`voxposer.places`) its median speed over ``ee_speed`` lies in the velocity word's
band. Only combinations whose place lies inside the region are drawn (so the region is crossed).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import VELOCITY_SCALE, ee_at_place, speed_clause
from voxposer.bench.primitives_programs import place_target, primitives_program
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, clear_at, move_to_place_programs
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.places import get_place

#: The baseline sets the speed this far outside the region's boundary [m] (on the straight way
#: in, perpendicular to it).
PRIM_BEFORE_M = 0.05


class VelocityInRegion(BenchTask):
    name = "move_to_pos_velocity_in_region"
    category = "Spatial Composition"
    template = "move to the [pos] while moving at [velocity] in the [region]"
    paper_row = "move to the [pos] while moving at [velocity] in the [region]"

    def compatible(self, attrs: dict[str, str]) -> bool:
        region = get_place(attrs["region"])
        return bool(region.margin(get_place(attrs["pos"]).point, 0.0) >= 0.05)

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        return block_layout({})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return clear_at(get_place(attrs["pos"]).point)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        ok, why = ee_at_place(trace.ee[-1], get_place(attrs["pos"]), tol)
        zone = get_place(attrs["region"]).contains(trace.ee[:, :2], tol.corner_radius_m)
        speed_ok, speed_why, metrics = speed_clause(
            trace, zone, attrs["velocity"], world.config.controller.ee_speed, tol)
        return Verdict(ok and speed_ok, f"{why}; {speed_why}", metrics)

    constraint = "velocity map"

    def blind(self, attrs: dict[str, str]) -> Programs:
        subtask = self.instruction(attrs)
        return move_to_place_programs(subtask, subtask, get_place(attrs["pos"]), None)

    def reference(self, attrs: dict[str, str]) -> Programs:
        place, region, vel = get_place(attrs["pos"]), get_place(attrs["region"]), \
            attrs["velocity"]
        subtask = self.instruction(attrs)
        velq = f"{vel} in the {region.name}"
        progs = move_to_place_programs(subtask, subtask, place, "velocity", velq)
        return progs.add("get_velocity_map", velq, "velocity_map = get_empty_velocity_map()",
                         "table = parse_query_obj('table')",
                         f"velocity_map[region_mask(table, '{region.words}')] = "
                         f"{VELOCITY_SCALE[vel]}", "ret_val = velocity_map")

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        place, region = get_place(attrs["pos"]), get_place(attrs["region"])
        k, edge = region.axis, region.bound - region.sign * PRIM_BEFORE_M
        return primitives_program(self.instruction(attrs), [
            f"target = {place_target(place)}",
            # at the default speed to just outside the region, then into it at the velocity
            "before = target.copy()", f"before[{k}] = {edge:g}",
            "move_to_pos(before)", f"set_vel({VELOCITY_SCALE[attrs['velocity']]:g})",
            "move_to_pos(target)", "set_vel(1.0)"])
