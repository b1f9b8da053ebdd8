"""Task "close the [deixis] drawer by pushing" (Object Interactions).

Reset: the cabinet stands at (−0.05, 0.37); the named drawer is open 10–18 cm, the others
closed. Success: the named drawer is open less than ``drawer_closed_m``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from voxposer.bench.attributes import DEIXIS_DRAWER
from voxposer.bench.config import Tolerances
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, one_subtask
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout

OPENING_M = (0.10, 0.18)


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
