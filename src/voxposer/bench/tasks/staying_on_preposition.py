"""Task "move to the [pos] while staying on the [preposition] the [obj]" (Spatial Composition).

"Staying on the left of the block" means: while the end effector passes the block, it stays on
the block's left — beyond the plane of its left face (by at most ``side_slack_m`` across it).
"Passing" is being level with the block along the motion: within the block's extent + 1 cm on
the horizontal axis the motion runs along. "On the top of" means passing over the block: level
with it along the motion (start → place), within its footprint + 1 cm across, and above its top
face. Success also needs the end effector at the place at the end, and the block passed.

Reset (so that the constraint binds): the end effector starts low (6 cm above the table; 4 cm,
below the block's top, for "top of") 24–32 cm from the place's point — for a side preposition along the other horizontal axis — and the
block stands at the middle of the straight line between them. For a side, the block is shifted
0.5–1.5 cm toward the named side, so the line cuts through its other half and the shortest way
round passes on the wrong side (for left/right the hand starts turned 90° about the vertical,
its fingers opening along the motion, so that they do not sweep the block it passes); for "top of" it stands 1–2 cm beside the line, below which the
shortest way passes beside it. A program without the avoidance map (the constraint-blind control)
takes the shortest way.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import BLOCK_HALF, ee_at_place
from voxposer.bench.primitives_programs import place_target, primitives_program, vec
from voxposer.bench.programs import Programs, affordance_at_place
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import (
    LOW_START_Z,
    block_layout,
    gripper_composer,
    low_path,
    one_subtask,
    path_clear,
    place_query,
    start_above,
)
from voxposer.bench.tasks.move_to_preposition import SIDES
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.errors import LayoutError
from voxposer.places import get_place

#: How far the passing window reaches beyond the block's faces [m].
WINDOW_M = 0.01
#: Voxel slices of the forbidden space beside the block, from its voxel box ``lo``, ``hi``:
#: from 3 voxels short of the named face to the other side, over the block's extent along the
#: motion (+ 8 voxels); for "top of", everything below its top face.
FORBIDDEN = {"left of": "avoidance_map[lo[0] - 8:hi[0] + 9, lo[1] - 3:, :] = 1",
             "right of": "avoidance_map[lo[0] - 8:hi[0] + 9, :hi[1] + 4, :] = 1",
             "front side of": "avoidance_map[:hi[0] + 4, lo[1] - 8:hi[1] + 9, :] = 1",
             "back side of": "avoidance_map[lo[0] - 3:, lo[1] - 8:hi[1] + 9, :] = 1",
             "top of": "avoidance_map[:, :, :hi[2] + 1] = 1"}
#: For "top of", the block stands this far (lo, hi) beside the straight line [m], either side,
#: so the shortest way round it is to that side.
TOP_LATERAL_M = (0.01, 0.02)
#: For "top of", the end effector starts this high [m]: below the block's top (5 cm), so the
#: shortest way passes beside the block and only a program that keeps above its top passes
#: over it.
TOP_START_Z = 0.04
#: Height of the place a correct program aims for [cm].
HEIGHT_CM = 5
#: The baseline passes the block through two points this far before and past its centre along
#: the way, this far beyond the named face (beside it) or above its top ("top of") [m].
PRIM_ALONG_M, PRIM_BEYOND_M, PRIM_ABOVE_M = 0.06, 0.04, 0.03


def _directions(prep: str) -> tuple[tuple[float, float], ...] | None:
    """Directions (target → start) the motion may run along: the axis across the named side."""
    axis = SIDES[prep][0]
    if axis == 2:
        return None
    return ((1.0, 0.0), (-1.0, 0.0)) if axis == 1 else ((0.0, 1.0), (0.0, -1.0))


def passing_margin(trace: Trace, block: np.ndarray, prep: str) -> tuple[int, float]:
    """(samples level with the block, the smallest margin [m] on the named side over them)."""
    axis, sign, _ = SIDES[prep]
    ee = trace.ee
    if axis < 2:
        other = 1 - axis
        level = np.abs(ee[:, other] - block[:, other]) <= BLOCK_HALF + WINDOW_M
        margin = sign * (ee[:, axis] - (block[:, axis] + sign * BLOCK_HALF))
    else:
        d = ee[-1, :2] - ee[0, :2]
        u = d / max(float(np.linalg.norm(d)), 1e-9)
        n = np.array([-u[1], u[0]])
        rel = ee[:, :2] - block[:, :2]
        level = np.abs(rel @ u) <= BLOCK_HALF + WINDOW_M
        over = np.abs(rel @ n) <= BLOCK_HALF + WINDOW_M
        above = ee[:, 2] - (block[:, 2] + BLOCK_HALF)
        margin = np.where(over, above, np.minimum(above, -(np.abs(rel @ n) - BLOCK_HALF)))
    if not np.any(level):
        return 0, float("inf")
    return int(np.sum(level)), float(np.min(margin[level]))


class StayingOnPreposition(BenchTask):
    name = "move_to_pos_staying_on_preposition"
    category = "Spatial Composition"
    template = "move to the [pos] while staying on the [preposition] the [obj]"
    paper_row = "move to the [pos] while staying on the [preposition] the [obj]"
    constraint = "avoidance map"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        target = get_place(attrs["pos"]).point
        prep = attrs["preposition"]
        length = float(rng.uniform(0.24, 0.32))
        side = 1.0 if rng.uniform() < 0.5 else -1.0
        found = low_path(rng, target, (length, length), (length / 2, length / 2),
                         (side * TOP_LATERAL_M[0], side * TOP_LATERAL_M[1])
                         if SIDES[prep][0] == 2 else (0.0, 0.0), _directions(prep))
        if found is None:
            raise LayoutError(f"no low start {length:.2f} m from the {attrs['pos']}")
        start, block = found
        axis, sign, _ = SIDES[prep]
        xy = list(block)
        if axis < 2:
            xy[axis] += sign * float(rng.uniform(0.005, 0.015))
        z = TOP_START_Z if axis == 2 else LOW_START_Z
        # passing a block beside it along x, the open fingers (4.3 cm to either side along y
        # at yaw 0) would sweep it: the hand starts turned so that they open along the motion
        yaw = math.pi / 2 if axis == 1 else 0.0
        return block_layout({attrs["obj"]: (xy[0], xy[1])}, ee_start=start_above(start, z),
                            ee_start_yaw=yaw)

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return path_clear(world, get_place(attrs["pos"]).point)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        ok, why = ee_at_place(trace.ee[-1], get_place(attrs["pos"]), tol)
        word = SIDES[attrs["preposition"]][2]
        level, margin = passing_margin(trace, trace.objects[attrs["obj"]], attrs["preposition"])
        if level == 0:
            return Verdict(False, f"never passed the {attrs['obj']}; {why}",
                           {"passing_samples": 0.0})
        if margin < -tol.side_slack_m:
            ok = False
            why = f"passed {-margin * 100:.1f} cm off the {word} side; " + why
        else:
            why = f"passed on the {word} side ({margin * 100:.1f} cm to spare); " + why
        return Verdict(ok, why, {"passing_samples": float(level), "min_side_margin": margin})

    def _programs(self, attrs: dict[str, str], blind: bool) -> Programs:
        place, prep, obj = get_place(attrs["pos"]), attrs["preposition"], attrs["obj"]
        subtask = self.instruction(attrs)
        aff = place_query(place.name, HEIGHT_CM)
        avoid = f"the space beyond the {SIDES[prep][2]} face of the {obj} on the other side"
        maps = {"affordance": aff} if blind else {"affordance": aff, "avoidance": avoid}
        progs = one_subtask(Programs(), subtask, subtask, reset=False)
        gripper_composer(progs, subtask, maps)
        progs.add("get_affordance_map", aff, *affordance_at_place(place, HEIGHT_CM))
        if blind:
            return progs
        return progs.add("get_avoidance_map", avoid, "avoidance_map = get_empty_avoidance_map()",
                         f"block = parse_query_obj('{obj}')", "lo, hi = block.aabb",
                         FORBIDDEN[prep], "ret_val = avoidance_map")

    def blind(self, attrs: dict[str, str]) -> Programs:
        return self._programs(attrs, blind=True)

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        axis, sign, _ = SIDES[attrs["preposition"]]
        if axis == 2:  # over the top face
            offset = f"np.array([0.0, 0.0, block.aabb[1][2] + {PRIM_ABOVE_M} - z])"
        else:  # beyond the named face, at the hand's height
            side = [0.0, 0.0, 0.0]
            side[axis] = sign * (BLOCK_HALF + PRIM_BEYOND_M)
            offset = vec(*side)
        return primitives_program(self.instruction(attrs), [
            f"block = detect('{attrs['obj']}')", "hand = detect('gripper')",
            f"target = {place_target(get_place(attrs['pos']))}",
            "u = target[:2] - hand.position[:2]", "u = u / np.linalg.norm(u)",
            # the hand's height: its fingertips 1.2 cm above its box's bottom
            "z = hand.aabb[0][2] + 0.012",
            "close_gripper()",
            *(f"move_to_pos(np.array([block.position[0] {s} {PRIM_ALONG_M} * u[0], "
              f"block.position[1] {s} {PRIM_ALONG_M} * u[1], z]) + {offset})"
              for s in "-+"),
            "move_to_pos(target)"])

    def reference(self, attrs: dict[str, str]) -> Programs:
        return self._programs(attrs, blind=False)
