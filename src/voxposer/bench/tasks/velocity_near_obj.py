"""Task "move to the [pos] while moving at [velocity] when within [dist]cm from the [obj]"
(Spatial Composition; Table 4 writes "from the obj").

"Within [dist]cm" is the end effector's distance to the block's faces
(:func:`~voxposer.bench.measures.block_distance`). Success: the end effector ends at the place,
and inside the zone its median speed over the controller's default ``ee_speed`` lies in the
velocity word's band (:func:`speed_clause`, which needs ``speed_min_samples`` in the zone).

Reset (so that the constraint binds): the end effector starts low (6 cm above the table)
24–32 cm from the place's point, and the block stands at the middle of the straight line
between them (within 1.5 cm of it). Every path to the place passes the block within a few
centimetres, so it crosses the zone for ≥ 5 cm (the block's width) at every [dist]; a program
without the velocity map (the constraint-blind control) moves there at the default speed,
outside every band.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import (
    BLOCK_HALF,
    VELOCITY_SCALE,
    block_distance,
    ee_at_place,
    speed_clause,
)
from voxposer.bench.primitives_programs import place_target, primitives_program
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

#: Extra radius a correct velocity map gives the zone: the block's half-extent (the map's sphere
#: is centred on the block, the distance counts from its faces) plus 5 cm, so the speed has
#: changed on entry [cm].
ZONE_MARGIN_CM = 8
#: The baseline changes speed this far beyond [dist] from the block's side faces [m]; between
#: those points it passes over the block this far above its top [m].
PRIM_SWITCH_M, PRIM_OVER_M = 0.03, 0.025


class VelocityNearObj(BenchTask):
    name = "move_to_pos_velocity_near_obj"
    category = "Spatial Composition"
    template = "move to the [pos] while moving at [velocity] when within [dist]cm from the [obj]"
    paper_row = "move to the [pos] while moving at [velocity] when within [dist]cm from the obj"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        target = get_place(attrs["pos"]).point
        length = float(rng.uniform(0.24, 0.32))
        found = low_path(rng, target, (length, length), (length / 2, length / 2),
                         (-0.015, 0.015))
        if found is None:
            raise LayoutError(f"no low start {length:.2f} m from the {attrs['pos']}")
        start, block = found
        return block_layout({attrs["obj"]: block}, ee_start=start_above(start))

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return path_clear(world, get_place(attrs["pos"]).point)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        ok, why = ee_at_place(trace.ee[-1], get_place(attrs["pos"]), tol)
        block = trace.objects[attrs["obj"]]
        zone = block_distance(trace.ee, block) <= float(attrs["dist"]) / 100
        speed_ok, speed_why, metrics = speed_clause(
            trace, zone, attrs["velocity"], world.config.controller.ee_speed, tol)
        return Verdict(ok and speed_ok, f"{why}; {speed_why}", metrics)

    constraint = "velocity map"

    def blind(self, attrs: dict[str, str]) -> Programs:
        subtask = self.instruction(attrs).replace(" from the ", " of the ")
        return move_to_place_programs(self.instruction(attrs), subtask,
                                      get_place(attrs["pos"]), None)

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

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        place, obj, dist = get_place(attrs["pos"]), attrs["obj"], int(attrs["dist"]) / 100
        vel = VELOCITY_SCALE[attrs["velocity"]]
        return primitives_program(self.instruction(attrs), [
            f"block = detect('{obj}')", "hand = detect('gripper')",
            f"target = {place_target(place)}",
            "b, s, t = block.position[:2], hand.position[:2], target[:2]",
            "u = (t - s) / np.linalg.norm(t - s)",
            f"z = block.aabb[1][2] + {PRIM_OVER_M}",
            # the speed changes r from the block's centre, on the way in and on the way out
            f"r = {BLOCK_HALF} + {dist:g} + {PRIM_SWITCH_M}",
            "if np.linalg.norm(s - b) > r:",
            "    p = b - r * u",
            "    move_to_pos(np.array([p[0], p[1], z]))",
            f"    set_vel({vel:g})",
            "else:",
            f"    set_vel({vel:g})",
            "    move_to_pos(np.array([s[0], s[1], z]))",
            "if np.linalg.norm(t - b) > r:",
            "    p = b + r * u",
            "    move_to_pos(np.array([p[0], p[1], z]))",
            "    set_vel(1.0)",
            "move_to_pos(target)",
            "set_vel(1.0)"])
