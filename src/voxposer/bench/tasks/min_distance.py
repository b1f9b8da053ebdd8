"""Task "move to the [pos] while staying at least [dist]cm from the [obj]" (Spatial Composition).

"At least [dist]cm from the block" is the distance from the end effector to the block's faces
(:func:`~voxposer.bench.measures.block_distance`). Success: the end effector ends at the place,
and the minimum of that distance over the whole motion is at least dist − ``min_dist_slack_m``.

Reset (so that the constraint binds): the end effector starts low (6 cm above the table) on the
far side of the block; the block stands beside the straight line from the start to the place's
point, 0.3–0.6 × [dist] off it, so the line passes within [dist] of its faces; dist + 6–9 cm lie
between its faces and the place's point and dist + 6–10 cm between them and the start. A program
that ignores the distance (the constraint-blind control) takes the short way past the block; a
correct avoidance map keeps the path out of the dist-cm shell.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import BLOCK_HALF, block_distance, ee_at_place
from voxposer.bench.primitives_programs import BACK_X_M, place_target, primitives_program
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import (
    block_layout,
    low_path,
    move_to_place_programs,
    path_clear,
    start_above,
)
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.errors import LayoutError
from voxposer.places import get_place

#: Extra radius a correct avoidance map adds to the stated distance: the block's half-extent
#: (the map's sphere is centred on the block, the distance counts from its faces) plus 2 cm [cm].
AVOID_MARGIN_CM = 5
#: The block stands this fraction (lo, hi) of [dist] beside the straight line (either side):
#: close enough that the line passes within [dist] of its faces, far enough that a correct
#: avoidance map's detour stays short.
LATERAL = (0.3, 0.6)
#: The baseline's hand goes round the block through two points this far beyond [dist] from
#: its side face, and this far before and past its centre along the way [m] …
PRIM_AROUND_M = (0.04, 0.04)
#: … or over it, this far above its top beyond [dist] [m].
PRIM_OVER_M = 0.05


class MinDistance(BenchTask):
    name = "move_to_pos_min_distance"
    category = "Spatial Composition"
    template = "move to the [pos] while staying at least [dist]cm from the [obj]"
    paper_row = "move to the [pos] while staying at least [dist]cm from the [obj]"
    constraint = "avoidance map"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        target = get_place(attrs["pos"]).point
        dist = float(attrs["dist"]) / 100
        near = dist + BLOCK_HALF + float(rng.uniform(0.06, 0.09))
        far = near + 2 * BLOCK_HALF + dist + float(rng.uniform(0.06, 0.10))
        side = 1.0 if rng.uniform() < 0.5 else -1.0
        lateral = (side * LATERAL[0] * dist, side * LATERAL[1] * dist)
        found = low_path(rng, target, (far, far), (near, near),
                         (min(lateral), max(lateral)))
        if found is None:
            raise LayoutError(f"no low start {far:.2f} m from the {attrs['pos']}")
        start, block = found
        return block_layout({attrs["obj"]: block}, ee_start=start_above(start))

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return path_clear(world, get_place(attrs["pos"]).point)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        ok, why = ee_at_place(trace.ee[-1], get_place(attrs["pos"]), tol)
        closest = float(np.min(block_distance(trace.ee, trace.objects[attrs["obj"]])))
        need = float(attrs["dist"]) / 100 - tol.min_dist_slack_m
        if closest < need:
            ok = False
        return Verdict(ok, f"{why}; closest {closest * 100:.1f} cm from the {attrs['obj']}'s "
                       f"faces (needs >= {need * 100:.1f})", {"closest": closest})

    def blind(self, attrs: dict[str, str]) -> Programs:
        subtask = self.instruction(attrs)
        return move_to_place_programs(subtask, subtask, get_place(attrs["pos"]), None)

    def reference(self, attrs: dict[str, str]) -> Programs:
        place, obj, dist = get_place(attrs["pos"]), attrs["obj"], int(attrs["dist"])
        subtask = self.instruction(attrs)
        avoid = f"at least {dist}cm away from the {obj}"
        progs = move_to_place_programs(subtask, subtask, place, "avoidance", avoid)
        return progs.add("get_avoidance_map", avoid, "avoidance_map = get_empty_avoidance_map()",
                         f"block = parse_query_obj('{obj}')",
                         f"set_voxel_by_radius(avoidance_map, block.position, "
                         f"{dist + AVOID_MARGIN_CM}, 1)", "ret_val = avoidance_map")

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        place, obj, dist = get_place(attrs["pos"]), attrs["obj"], int(attrs["dist"]) / 100
        path = _over_lines(dist) if place.point[0] < BACK_X_M else _around_lines(dist)
        return primitives_program(self.instruction(attrs), [
            f"block = detect('{obj}')", "hand = detect('gripper')",
            f"target = {place_target(place)}", *path, "move_to_pos(target)"])


def _around_lines(dist: float) -> list[str]:
    """Baseline code going round the block at the place's height, through two points ``dist``
    [m] + margin beyond its side face, on the side of the way away from it (over it instead
    when those points lie near the base)."""
    over = "\n".join("    " + line for line in _over_lines(dist))
    return [
        "b, s = block.position[:2], hand.position[:2]",
        "u = (target[:2] - s) / np.linalg.norm(target[:2] - s)",
        "n = np.array([-u[1], u[0]])",
        "if np.dot(b - s, n) > 0:",
        "    n = -n",
        f"r = {BLOCK_HALF} + {dist:g} + {PRIM_AROUND_M[0]}",
        f"points = [b + r * n - {PRIM_AROUND_M[1]} * u, b + r * n + {PRIM_AROUND_M[1]} * u]",
        f"if min(points[0][0], points[1][0]) < {BACK_X_M}:",
        over,
        "else:",
        "    for p in points:",
        "        move_to_pos(np.array([p[0], p[1], target[2]]))"]


def _over_lines(dist: float) -> list[str]:
    """Baseline code going over the block ``dist`` [m] + margin above its top (up where the
    hand stands, across, then down at the place): near the base, where the hand swings when it
    moves across in front of it low."""
    return [f"z = block.aabb[1][2] + {dist:g} + {PRIM_OVER_M}",
            "move_to_pos(np.array([hand.position[0], hand.position[1], z]))",
            "move_to_pos(np.array([target[0], target[1], z]))"]
