"""Task "grasp the [obj] from the table at [velocity]" (Object Interactions).

Success: at the end the block is held — its centre within ``held_distance_m`` of the end
effector, the fingers between ``held_opening_m`` — and lifted ``lift_m`` off the table; and while
the gripper was still open (the approach) the end effector's median speed over ``ee_speed`` lies
in the velocity word's band.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import BLOCK_HALF, VELOCITY_SCALE, sample_xy, speed_clause
from voxposer.bench.primitives_programs import grasp_lines, primitives_program
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, gripper_composer
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout


def held_verdict(world: Any, obj: str, tol: Tolerances) -> tuple[bool, str, dict[str, float]]:
    """Whether ``obj`` is held in the closed gripper and lifted off the table."""
    block = world.object_position(obj)
    dist = float(np.linalg.norm(block - world.get_ee_pose()[0]))
    opening = float(world.gripper_opening())
    lifted = float(block[2] - BLOCK_HALF)
    ok = (dist <= tol.held_distance_m and tol.held_opening_m[0] <= opening <= tol.held_opening_m[1]
          and lifted >= tol.lift_m)
    return ok, (f"block {dist * 100:.1f} cm from the hand, fingers {opening * 100:.1f} cm apart, "
                f"lifted {lifted * 100:.1f} cm"), {"hand_dist": dist, "opening": opening,
                                                   "lifted": lifted}


def grasp_programs(progs: Programs, obj: str, velocity: str | None = None, *,
                   blind: bool = False) -> Programs:
    """Composer + map programs grasping ``obj`` top-down (at a velocity word's speed; with
    ``blind`` the sub-task still names the speed but no velocity map is built)."""
    subtask = f"grasp the {obj}" + (f" while moving at {velocity}" if velocity else "")
    maps = {"affordance": f"a point at the center of the {obj}", "rotation": "top-down",
            "gripper": f"open everywhere except 1cm around the {obj}"}
    if velocity and not blind:
        maps["velocity"] = f"{velocity} everywhere"
        progs.add("get_velocity_map", maps["velocity"], "velocity_map = get_empty_velocity_map()",
                  f"velocity_map[:] = {VELOCITY_SCALE[velocity]}", "ret_val = velocity_map")
    gripper_composer(progs, subtask, maps)
    progs.add("get_affordance_map", maps["affordance"], "affordance_map = get_empty_affordance_map()",
              f"block = parse_query_obj('{obj}')", "x, y, z = block.position",
              "affordance_map[x, y, z] = 1", "ret_val = affordance_map")
    progs.add("get_rotation_map", "top-down", "rotation_map = get_empty_rotation_map()",
              "rotation_map[:, :, :] = pointat2quat([0, 0, -1])", "ret_val = rotation_map")
    return progs.add("get_gripper_map", maps["gripper"], "gripper_map = get_empty_gripper_map()",
                     f"block = parse_query_obj('{obj}')", "gripper_map[:] = 0",
                     "set_voxel_by_radius(gripper_map, block.position, 1, 1)",
                     "ret_val = gripper_map")


class GraspAtVelocity(BenchTask):
    name = "grasp_at_velocity"
    category = "Object Interactions"
    template = "grasp the [obj] from the table at [velocity]"
    paper_row = "grasp the [obj] from the table at [velocity]"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        return block_layout({attrs["obj"]: sample_xy(rng, (-0.30, -0.25), (0.05, 0.25))})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return [(tuple(world.object_position(attrs["obj"])[:2]), 0.12)]

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        ok, why, metrics = held_verdict(world, attrs["obj"], tol)
        approach = np.cumsum(trace.gripper >= 0.5) == 0
        speed_ok, speed_why, m2 = speed_clause(
            trace, approach, attrs["velocity"], world.config.controller.ee_speed, tol)
        return Verdict(ok and speed_ok, f"{why}; approach: {speed_why}", {**metrics, **m2})

    constraint = "velocity map"

    def blind(self, attrs: dict[str, str]) -> Programs:
        return self.reference(attrs, blind=True)

    def reference(self, attrs: dict[str, str], *, blind: bool = False) -> Programs:
        obj, vel = attrs["obj"], attrs["velocity"]
        progs = Programs().add("planner", self.instruction(attrs),
                               f"composer('grasp the {obj} while moving at {vel}')",
                               "composer('back to default pose')")
        progs.add("composer", "back to default pose", "reset_to_default_pose()")
        return grasp_programs(progs, obj, vel, blind=blind)

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        return primitives_program(self.instruction(attrs), grasp_lines(
            attrs["obj"], VELOCITY_SCALE[attrs["velocity"]]))
