"""Task "move to the [preposition] the [obj]" (Spatial Composition).

Success: the end effector ends beside the block on the named side — beyond that face by
``beside_gap_m``, within ``beside_lateral_m`` across it and below ``beside_max_height_m`` — or,
for "top of", ``above_height_m`` above its top face within ``above_lateral_m`` horizontally.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import BLOCK_HALF, sample_xy
from voxposer.bench.primitives_programs import primitives_program, vec
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, clear_at, gripper_composer, one_subtask
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout

#: preposition → (axis, sign) of the side, and the API's side word.
SIDES = {"left of": (1, -1, "left"), "right of": (1, 1, "right"), "front side of": (0, 1, "front"),
         "back side of": (0, -1, "back"), "top of": (2, 1, "top")}
#: How far beside the block a correct program aims [cm].
OFFSET_CM = 5
#: The baseline's target from the block's centre [m]: beside it (this far from the centre
#: along the side's axis, this high) or above it (this high).
PRIM_BESIDE_M, PRIM_BESIDE_Z_M, PRIM_ABOVE_M = 0.08, 0.03, 0.08


def beside_verdict(ee: np.ndarray, block: np.ndarray, preposition: str,
                   tol: Tolerances) -> Verdict:
    """Is the end effector at ``ee`` [m] on the ``preposition`` side of a block at ``block``?"""
    axis, sign, _ = SIDES[preposition]
    d = ee - block
    if axis == 2:
        height = d[2] - BLOCK_HALF
        lateral = float(np.hypot(d[0], d[1]))
        ok = tol.above_height_m[0] <= height <= tol.above_height_m[1] and \
            lateral <= tol.above_lateral_m
        return Verdict(ok, f"{height * 100:.1f} cm above the top, {lateral * 100:.1f} cm off "
                       "centre", {"height": height, "lateral": lateral})
    gap = sign * d[axis] - BLOCK_HALF
    lateral = abs(float(d[1 - axis]))
    ok = (tol.beside_gap_m[0] <= gap <= tol.beside_gap_m[1] and lateral <= tol.beside_lateral_m
          and ee[2] <= tol.beside_max_height_m)
    return Verdict(ok, f"{gap * 100:.1f} cm beyond the {SIDES[preposition][2]} face, "
                   f"{lateral * 100:.1f} cm across, {ee[2] * 100:.0f} cm high",
                   {"gap": gap, "lateral": lateral, "height": float(ee[2])})


class MoveToPreposition(BenchTask):
    name = "move_to_preposition"
    category = "Spatial Composition"
    template = "move to the [preposition] the [obj]"
    paper_row = "move to the [preposition] the [obj]"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        xy = sample_xy(rng, (-0.25, -0.22), (0.02, 0.22))
        return block_layout({attrs["obj"]: xy})

    def _target(self, attrs: dict[str, str], block_xy: np.ndarray) -> tuple[float, float]:
        axis, sign, _ = SIDES[attrs["preposition"]]
        p = np.array(block_xy[:2], dtype=float)
        if axis < 2:
            p[axis] += sign * (BLOCK_HALF + OFFSET_CM / 100)
        return float(p[0]), float(p[1])

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return clear_at(self._target(attrs, world.object_position(attrs["obj"])))

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        return beside_verdict(trace.ee[-1], world.object_position(attrs["obj"]),
                              attrs["preposition"], tol)

    def reference(self, attrs: dict[str, str]) -> Programs:
        obj, prep = attrs["obj"], attrs["preposition"]
        word = SIDES[prep][2]
        subtask = f"move to the {prep} the {obj}"
        query = f"a point {OFFSET_CM}cm {'above' if word == 'top' else word + ' of'} the {obj}"
        progs = one_subtask(Programs(), self.instruction(attrs), subtask, reset=False)
        gripper_composer(progs, subtask, {"affordance": query})
        return progs.add("get_affordance_map", query,
                         "affordance_map = get_empty_affordance_map()",
                         f"block = parse_query_obj('{obj}')",
                         f"x, y, z = point_beside(block, '{word}', {OFFSET_CM})",
                         "affordance_map[x, y, z] = 1",
                         "ret_val = affordance_map")

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        return primitives_program(self.instruction(attrs),
                                  beside_lines(attrs["obj"], attrs["preposition"]))


def beside_lines(obj: str, preposition: str) -> list[str]:
    """Baseline code moving the fingertips to the ``preposition`` side of ``obj``: down from
    10 cm above the point beside it, fingers closed (they would straddle its face open)."""
    axis, sign, _ = SIDES[preposition]
    offset = [0.0, 0.0, PRIM_ABOVE_M] if axis == 2 else [0.0, 0.0, PRIM_BESIDE_Z_M]
    if axis < 2:
        offset[axis] = sign * PRIM_BESIDE_M
    lines = [f"block = detect('{obj}')", f"target = block.position + {vec(*offset)}"]
    if axis == 2:
        return [*lines, "move_to_pos(target)"]
    return [*lines, "close_gripper()", "move_to_pos(target + np.array([0.0, 0.0, 0.10]))",
            "move_to_pos(target)"]
