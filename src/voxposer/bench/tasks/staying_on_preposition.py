"""Task "move to the [pos] while staying on the [preposition] the [obj]" (Spatial Composition).

"Staying on the left of the block" means the end effector never crosses the plane of the block's
left face (by more than ``side_slack_m``) during the whole motion; "on the top of" means never
below the block's top face. Success also needs the end effector at the place at the end.
Reset: the start and the place are on the stated side with ≥ 5 cm to spare (combinations where
that is impossible are redrawn), and the block stands near the straight path.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import BLOCK_HALF, ee_at_place, sample_xy
from voxposer.bench.programs import Programs, affordance_at_place
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import (
    EE_START_XY,
    block_layout,
    clear_at,
    gripper_composer,
    one_subtask,
    place_query,
    toward,
)
from voxposer.bench.tasks.move_to_preposition import SIDES
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.envs.places import get_place

BOX_LO, BOX_HI = (-0.34, -0.30), (0.10, 0.30)
SPARE_M = 0.05
#: Voxel slices of the forbidden half-space, from the block's voxel box ``lo``, ``hi``.
FORBIDDEN = {"left of": "avoidance_map[:, lo[1]:, :] = 1",
             "right of": "avoidance_map[:, :hi[1] + 1, :] = 1",
             "front side of": "avoidance_map[:hi[0] + 1, :, :] = 1",
             "back side of": "avoidance_map[lo[0]:, :, :] = 1",
             "top of": "avoidance_map[:, :, :hi[2] + 1] = 1"}


def block_range(prep: str, target: tuple[float, float]) -> tuple[int, float, float] | None:
    """(axis, lo, hi) of the block centre coordinate that keeps the start and ``target`` on the
    ``prep`` side with room to spare, or None when impossible (None also for "top of")."""
    axis, sign, _ = SIDES[prep]
    if axis == 2:
        return None
    pts = (EE_START_XY[axis], target[axis])
    need = BLOCK_HALF + SPARE_M
    if sign < 0:  # points must be at <= face - spare: block >= max + need
        return axis, max(pts) + need, BOX_HI[axis]
    return axis, BOX_LO[axis], min(pts) - need


class StayingOnPreposition(BenchTask):
    name = "move_to_pos_staying_on_preposition"
    category = "Spatial Composition"
    template = "move to the [pos] while staying on the [preposition] the [obj]"
    paper_row = "move to the [pos] while staying on the [preposition] the [obj]"

    def compatible(self, attrs: dict[str, str]) -> bool:
        rng = block_range(attrs["preposition"], get_place(attrs["pos"]).point)
        return rng is None or rng[2] - rng[1] >= 0.02

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        target = get_place(attrs["pos"]).point
        span = block_range(attrs["preposition"], target)
        if span is None:  # "top of": near the middle of the path
            xy = toward(EE_START_XY, target, 0.5 * float(np.hypot(target[0] - EE_START_XY[0],
                        target[1] - EE_START_XY[1])), float(rng.uniform(-0.05, 0.05)))
            return block_layout({attrs["obj"]: xy})
        axis, lo, hi = span
        box_lo, box_hi = list(BOX_LO), list(BOX_HI)
        box_lo[axis], box_hi[axis] = lo, hi
        return block_layout({attrs["obj"]: sample_xy(rng, (box_lo[0], box_lo[1]), (box_hi[0], box_hi[1]))})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return clear_at(get_place(attrs["pos"]).point)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        ok, why = ee_at_place(trace.ee[-1], get_place(attrs["pos"]), tol)
        axis, sign, word = SIDES[attrs["preposition"]]
        block = trace.objects[attrs["obj"]]
        face = block[:, axis] + sign * BLOCK_HALF
        inside = float(np.min(sign * (trace.ee[:, axis] - face)))
        if inside < -tol.side_slack_m:
            ok = False
            why = f"crossed to the other side of the {word} face by {-inside * 100:.1f} cm; " + why
        return Verdict(ok, why, {"min_side_margin": inside})

    def reference(self, attrs: dict[str, str]) -> Programs:
        place, prep, obj = get_place(attrs["pos"]), attrs["preposition"], attrs["obj"]
        height = 10 if prep == "top of" else 5
        subtask = self.instruction(attrs)
        aff = place_query(place.name, height)
        avoid = f"the space beyond the {SIDES[prep][2]} face of the {obj} on the other side"
        progs = one_subtask(Programs(), subtask, subtask, reset=False)
        gripper_composer(progs, subtask, {"affordance": aff, "avoidance": avoid})
        progs.add("get_affordance_map", aff, *affordance_at_place(place, height))
        return progs.add("get_avoidance_map", avoid, "avoidance_map = get_empty_avoidance_map()",
                         f"block = parse_query_obj('{obj}')", "lo, hi = block.aabb",
                         FORBIDDEN[prep], "ret_val = avoidance_map")
