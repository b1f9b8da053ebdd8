"""Task "close the [deixis] drawer by pushing" (Object Interactions).

Reset: the cabinet stands at (−0.05, 0.37); the named drawer is open 10–18 cm, the others
closed. Success: the named drawer is open less than ``drawer_closed_m``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.attributes import DEIXIS_DRAWER
from voxposer.bench.config import Tolerances
from voxposer.bench.primitives_programs import primitives_program
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, one_subtask
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout

OPENING_M = (0.10, 0.18)
#: A closed drawer whose handle shows where the named one's goes when closed (the nearest
#: drawer may be hidden under the open one).
CLOSED_REFERENCE = {"top": "bottom", "middle": "top", "bottom": "top"}
#: The baseline's fingertips: this far in front of the handle before the push, and this far
#: short of the closed handles' front face at its end [m].
PRIM_APPROACH_M, PRIM_SHORT_M = 0.06, 0.015


class CloseDrawer(BenchTask):
    name = "close_drawer"
    category = "Object Interactions"
    template = "close the [deixis] drawer by pushing"
    paper_row = "close the [deixis] drawer by pushing"

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        which = DEIXIS_DRAWER[attrs["deixis"]]
        return block_layout({}, cabinet=True, extra_blocks=(1, 3),
                            drawer_openings={which: float(rng.uniform(*OPENING_M))})

    def tracked(self, attrs: dict[str, str]) -> tuple[str, ...]:
        return ()

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        return [((-0.05, y), 0.17) for y in (-0.05, 0.08, 0.2)]

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        which = DEIXIS_DRAWER[attrs["deixis"]]
        opening = world.drawer_opening(which)
        ok = opening < tol.drawer_closed_m
        return Verdict(ok, f"the {which} drawer is open {opening * 100:.1f} cm", {"opening": opening})

    def reference(self, attrs: dict[str, str]) -> Programs:
        progs = Programs()
        subtask = push_handle_programs(progs, DEIXIS_DRAWER[attrs["deixis"]])
        return one_subtask(progs, self.instruction(attrs), subtask, reset=True)

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        which = DEIXIS_DRAWER[attrs["deixis"]]
        return primitives_program(self.instruction(attrs), push_drawer_lines(which))


def push_drawer_lines(which: str) -> list[str]:
    """Baseline code closing the ``which`` drawer: the hand turned to point its closed fingers
    at the cabinet (+y, the hand's length along x, so that it clears the table and the drawers
    above), in front of the handle at its height, pushes it in +y until it is level with a
    closed drawer's handle, then backs off."""
    return [
        f"handle = detect('{which} drawer handle')",
        f"closed = detect('{CLOSED_REFERENCE[which]} drawer handle')",
        "x, z = handle.position[0], handle.position[2]",
        "rotate_by_quat(np.array([0.5, 0.5, -0.5, 0.5]))",
        "close_gripper()",
        f"move_to_pos(np.array([x, handle.aabb[0][1] - {PRIM_APPROACH_M}, z]))",
        f"move_to_pos(np.array([x, closed.aabb[0][1] - {PRIM_SHORT_M}, z]))",
        f"move_to_pos(np.array([x, closed.aabb[0][1] - {PRIM_APPROACH_M + 0.04:.2f}, z]))",
    ]


def push_handle_programs(progs: Programs, which: str) -> str:
    """Composer + map programs pushing the ``which`` drawer's handle 25 cm in +y (closing it);
    returns the sub-task."""
    subtask = f"push the {which} drawer handle 25cm in the +y direction"
    query = f"a point 25cm in the +y direction from the {which} drawer handle"
    progs.add("composer", subtask, f"movable = parse_query_obj('{which} drawer handle')",
              f"affordance_map = get_affordance_map('{query}')",
              "execute(movable, affordance_map=affordance_map)")
    progs.add("get_affordance_map", query, "affordance_map = get_empty_affordance_map()",
              f"handle = parse_query_obj('{which} drawer handle')", "x, y, z = handle.position",
              "affordance_map[x, y + cm2index(25, 'y'), z] = 1", "ret_val = affordance_map")
    return subtask
