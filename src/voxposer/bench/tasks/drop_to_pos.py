"""Task "drop the [obj] to the [pos]" (Object Interactions).

Success: the block ends resting on the table at the place, released (gripper open).
Reset: the block starts at least 10 cm outside the place.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import block_at_place
from voxposer.bench.primitives_programs import (
    carry_and_drop_lines,
    grasp_lines,
    primitives_program,
)
from voxposer.bench.programs import Programs, affordance_at_place
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, gripper_composer, place_query
from voxposer.bench.tasks.grasp_at_velocity import grasp_programs
from voxposer.bench.tasks.push_to_pos import push_start
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.places import Place, get_place

#: Height above the table the block is carried to before it is released [cm].
CARRY_CM = 10


class DropToPos(BenchTask):
    name = "drop_to_pos"
    category = "Object Interactions"
    template = "drop the [obj] to the [pos]"
    paper_row = "drop the [obj] to the [pos]"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        return block_layout({attrs["obj"]: push_start(rng, get_place(attrs["pos"]), Tolerances())})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return [(tuple(world.object_position(attrs["obj"])[:2]), 0.12),
                (get_place(attrs["pos"]).point, 0.10)]

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        pos = world.object_position(attrs["obj"])
        ok, why = block_at_place(pos, get_place(attrs["pos"]), tol)
        released = world.get_gripper_state() < 0.5
        return Verdict(ok and released, why + ("" if released else "; still held"),
                       {"x": float(pos[0]), "y": float(pos[1]), "z": float(pos[2])})

    def reference(self, attrs: dict[str, str]) -> Programs:
        obj, place = attrs["obj"], get_place(attrs["pos"])
        progs = Programs()
        subtasks = [f"grasp the {obj}", "back to default pose",
                    *carry_and_release_programs(progs, obj, place), "back to default pose"]
        progs.add("planner", self.instruction(attrs), *(f"composer('{s}')" for s in subtasks))
        progs.add("composer", "back to default pose", "reset_to_default_pose()")
        return grasp_programs(progs, obj)

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        return primitives_program(self.instruction(attrs), [
            *grasp_lines(attrs["obj"]), *carry_and_drop_lines(get_place(attrs["pos"]))])


def carry_and_release_programs(progs: Programs, obj: str, place: Place) -> list[str]:
    """Composer + map programs carrying the held ``obj`` to ``CARRY_CM`` above ``place`` and
    releasing it there; returns the two sub-tasks (carry, release)."""
    carry = f"move the {obj} to a point {CARRY_CM}cm above the {place.name}"
    aff = place_query(place.name, CARRY_CM)
    gripper_composer(progs, carry, {"affordance": aff, "gripper": "close everywhere"})
    progs.add("get_affordance_map", aff, *affordance_at_place(place, CARRY_CM))
    progs.add("get_gripper_map", "close everywhere", "gripper_map = get_empty_gripper_map()",
              "gripper_map[:] = 1", "ret_val = gripper_map")
    # Release toward a fixed point: "5cm above the gripper" (the composer prompt's example)
    # is re-evaluated at every replanning step in closed loop and runs away upward.
    above = place_query(place.name, CARRY_CM + 5)
    gripper_composer(progs, f"release the {obj}",
                     {"affordance": above, "gripper": "open everywhere"})
    progs.add("get_affordance_map", above, *affordance_at_place(place, CARRY_CM + 5))
    progs.add("get_gripper_map", "open everywhere", "gripper_map = get_empty_gripper_map()",
              "gripper_map[:] = 0", "ret_val = gripper_map")
    return [carry, f"release the {obj}"]
