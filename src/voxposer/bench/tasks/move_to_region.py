"""Task "move to the [region]" (Spatial Composition).

Success: the end effector ends inside the region (a side of the table, see
:mod:`voxposer.places`) no higher than ``ee_max_height_m``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import ee_at_place
from voxposer.bench.primitives_programs import move_to_place, primitives_program
from voxposer.bench.programs import Programs, affordance_at_place
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, clear_at, gripper_composer, one_subtask
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.places import get_place

#: Height above the table a correct program aims for when moving to a table place [cm].
HOVER_CM = 5


class MoveToRegion(BenchTask):
    name = "move_to_region"
    category = "Spatial Composition"
    template = "move to the [region]"
    paper_row = "move to the [region]"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        return block_layout({})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return clear_at(get_place(attrs["region"]).point)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        ok, why = ee_at_place(trace.ee[-1], get_place(attrs["region"]), tol)
        return Verdict(ok, why, {"ee_height": float(trace.ee[-1][2])})

    def reference(self, attrs: dict[str, str]) -> Programs:
        place = get_place(attrs["region"])
        subtask = f"move to the {place.name}"
        query = f"a point {HOVER_CM}cm above the {place.name}"
        progs = one_subtask(Programs(), self.instruction(attrs), subtask, reset=False)
        gripper_composer(progs, subtask, {"affordance": query})
        return progs.add("get_affordance_map", query, *affordance_at_place(place, HOVER_CM))

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        return primitives_program(self.instruction(attrs), move_to_place(get_place(attrs["region"])))
