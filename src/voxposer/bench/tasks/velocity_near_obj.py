"""Task "move to the [pos] while moving at [velocity] when within [dist]cm from the [obj]"
(Spatial Composition; Table 4 writes "from the obj").

"Within [dist]cm" is the end effector–block-centre distance (as the prompts' velocity maps do).
Success: the end effector ends at the place, and inside the zone its median speed over the
controller's default ``ee_speed`` lies in the velocity word's band (:func:`speed_clause`).
Reset: the block stands 5–8 cm beside the place's point, across the way from the start, so
the end effector's final approach passes it (with small [dist] it may never come that close:
the speed clause then holds vacuously, and ``zone_samples`` = 0 says so).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import VELOCITY_SCALE, ee_at_place, speed_clause
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import (
    EE_START_XY,
    block_layout,
    clear_at,
    move_to_place_programs,
    toward,
)
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.envs.places import get_place

#: Extra radius a correct velocity map gives the zone, so the speed has changed on entry [cm].
ZONE_MARGIN_CM = 2


class VelocityNearObj(BenchTask):
    name = "move_to_pos_velocity_near_obj"
    category = "Spatial Composition"
    template = "move to the [pos] while moving at [velocity] when within [dist]cm from the [obj]"
    paper_row = "move to the [pos] while moving at [velocity] when within [dist]cm from the obj"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        target = get_place(attrs["pos"]).point
        side = 1.0 if rng.uniform() < 0.5 else -1.0
        xy = toward(target, EE_START_XY, float(rng.uniform(0.0, 0.03)),
                    side * float(rng.uniform(0.05, 0.08)))
        return block_layout({attrs["obj"]: xy})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return clear_at(get_place(attrs["pos"]).point)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        ok, why = ee_at_place(trace.ee[-1], get_place(attrs["pos"]), tol)
        block = trace.objects[attrs["obj"]]
        zone = np.linalg.norm(trace.ee - block, axis=1) <= float(attrs["dist"]) / 100
        speed_ok, speed_why, metrics = speed_clause(
            trace, zone, attrs["velocity"], world.config.controller.ee_speed, tol)
        return Verdict(ok and speed_ok, f"{why}; {speed_why}", metrics)

    def reference(self, attrs: dict[str, str]) -> Programs:
        place, obj, dist, vel = get_place(attrs["pos"]), attrs["obj"], attrs["dist"], \
            attrs["velocity"]
        subtask = self.instruction(attrs).replace(" from the ", " of the ")
        velq = f"{vel} within {dist}cm of the {obj}"
        progs = move_to_place_programs(self.instruction(attrs), subtask, place, "velocity", velq)
        return progs.add("get_velocity_map", velq, "velocity_map = get_empty_velocity_map()",
                         f"block = parse_query_obj('{obj}')",
                         f"set_voxel_by_radius(velocity_map, block.position, "
                         f"{int(dist) + ZONE_MARGIN_CM}, {VELOCITY_SCALE[vel]})",
                         "ret_val = velocity_map")
