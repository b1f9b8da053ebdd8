"""Task "move to the [pos] while staying at least [dist]cm from the [obj]" (Spatial Composition).

Success: the end effector ends at the place, and the minimum over the whole motion of its
distance to the block's centre is at least dist − ``min_dist_slack_m``. Reset: the block stands
on the way, dist + 5–9 cm before the place's point.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import ee_at_place
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

#: Extra radius a correct avoidance map adds to the stated distance [cm].
AVOID_MARGIN_CM = 2


class MinDistance(BenchTask):
    name = "move_to_pos_min_distance"
    category = "Spatial Composition"
    template = "move to the [pos] while staying at least [dist]cm from the [obj]"
    paper_row = "move to the [pos] while staying at least [dist]cm from the [obj]"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        target = get_place(attrs["pos"]).point
        r = float(attrs["dist"]) / 100 + float(rng.uniform(0.05, 0.09))
        return block_layout({attrs["obj"]: toward(target, EE_START_XY, r,
                                                  float(rng.uniform(-0.02, 0.02)))})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return clear_at(get_place(attrs["pos"]).point)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        ok, why = ee_at_place(trace.ee[-1], get_place(attrs["pos"]), tol)
        closest = float(np.min(np.linalg.norm(trace.ee - trace.objects[attrs["obj"]], axis=1)))
        need = float(attrs["dist"]) / 100 - tol.min_dist_slack_m
        if closest < need:
            ok = False
        return Verdict(ok, f"{why}; closest {closest * 100:.1f} cm from the {attrs['obj']} "
                       f"(needs >= {need * 100:.1f})", {"closest": closest})

    def reference(self, attrs: dict[str, str]) -> Programs:
        place, obj, dist = get_place(attrs["pos"]), attrs["obj"], int(attrs["dist"])
        subtask = self.instruction(attrs)
        avoid = f"at least {dist}cm away from the {obj}"
        progs = move_to_place_programs(subtask, subtask, place, "avoidance", avoid)
        return progs.add("get_avoidance_map", avoid, "avoidance_map = get_empty_avoidance_map()",
                         f"block = parse_query_obj('{obj}')",
                         f"set_voxel_by_radius(avoidance_map, block.position, "
                         f"{dist + AVOID_MARGIN_CM}, 1)", "ret_val = avoidance_map")
