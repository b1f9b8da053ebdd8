"""Steps that move the end effector: hover over a block, a table place, beside a block, away from
a block, and a table place while keeping a distance (a constraint clause).

Each reuses the 13 tasks' measures (:mod:`voxposer.bench.measures`) and reference pieces
(:mod:`voxposer.bench.tasks._common`), judged at every trace sample instead of at the end.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import BLOCK_HALF, block_distance
from voxposer.bench.multistep.step import Step
from voxposer.bench.programs import Programs, affordance_at_place
from voxposer.bench.tasks._common import gripper_composer, place_query
from voxposer.bench.tasks.min_distance import AVOID_MARGIN_CM
from voxposer.bench.tasks.move_to_preposition import OFFSET_CM, SIDES, beside_verdict
from voxposer.bench.tasks.move_to_region import HOVER_CM
from voxposer.bench.trace import Trace
from voxposer.places import get_place


def point_above_programs(progs: Programs, obj: str, cm: int, subtask: str = "") -> str:
    """Record a gripper move to the point ``cm`` above ``obj``'s top face as ``subtask``
    (default: "move to a point 10cm above the blue block"); returns the sub-task."""
    query = f"a point {cm}cm above the {obj}"
    subtask = subtask or f"move to {query}"
    gripper_composer(progs, subtask, {"affordance": query})
    progs.add("get_affordance_map", query, "affordance_map = get_empty_affordance_map()",
              f"block = parse_query_obj('{obj}')", f"x, y, z = point_beside(block, 'top', {cm})",
              "affordance_map[x, y, z] = 1", "ret_val = affordance_map")
    return subtask


@dataclass(frozen=True)
class Hover(Step):
    """The end effector within ``hover_radius_m`` of the point ``cm`` above ``obj``'s top."""

    obj: str
    cm: int = 10

    @property
    def label(self) -> str:
        return f"hover {self.cm}cm over the {self.obj}"

    def tracked(self) -> tuple[str, ...]:
        return (self.obj,)

    def _miss(self, trace: Trace) -> NDArray[np.float64]:
        """Distance [m] of the end effector from the hover point at each sample, shape (T,)."""
        target = trace.objects[self.obj] + np.array([0.0, 0.0, BLOCK_HALF + self.cm / 100])
        return np.asarray(np.linalg.norm(trace.ee - target, axis=1), dtype=np.float64)

    def held(self, world: Any, trace: Trace, tol: Tolerances) -> NDArray[np.bool_]:
        return self._miss(trace) <= tol.hover_radius_m

    def describe_end(self, world: Any, trace: Trace, tol: Tolerances) -> str:
        best = float(np.min(self._miss(trace)))
        return (f"closest {best * 100:.1f} cm from the point (needs <= "
                f"{tol.hover_radius_m * 100:.0f} cm)")

    def programs(self, progs: Programs) -> list[str]:
        return [point_above_programs(progs, self.obj, self.cm)]


@dataclass(frozen=True)
class AtPlace(Step):
    """The end effector at a table place, no higher than ``ee_max_height_m`` ("move to the
    [region]")."""

    place: str

    @property
    def label(self) -> str:
        return f"move to the {self.place}"

    def held(self, world: Any, trace: Trace, tol: Tolerances) -> NDArray[np.bool_]:
        inside = get_place(self.place).margin(trace.ee[:, :2], tol.corner_radius_m) >= 0
        return np.asarray(inside & (trace.ee[:, 2] <= tol.ee_max_height_m))

    def describe_end(self, world: Any, trace: Trace, tol: Tolerances) -> str:
        margin = float(get_place(self.place).margin(trace.ee[-1, :2], tol.corner_radius_m))
        return (f"the end effector ends {max(-margin, 0.0) * 100:.1f} cm outside it, "
                f"{trace.ee[-1, 2] * 100:.0f} cm high")

    def programs(self, progs: Programs) -> list[str]:
        place = get_place(self.place)
        subtask, query = f"move to the {place.name}", place_query(place.name, HOVER_CM)
        gripper_composer(progs, subtask, {"affordance": query})
        progs.add("get_affordance_map", query, *affordance_at_place(place, HOVER_CM))
        return [subtask]


@dataclass(frozen=True)
class Beside(Step):
    """The end effector on the ``preposition`` side of ``obj`` ("move to the left of the
    [obj]"), as the task move_to_preposition judges it."""

    obj: str
    preposition: str

    @property
    def label(self) -> str:
        return f"move to the {self.preposition} the {self.obj}"

    def tracked(self) -> tuple[str, ...]:
        return (self.obj,)

    def held(self, world: Any, trace: Trace, tol: Tolerances) -> NDArray[np.bool_]:
        block = trace.objects[self.obj]
        return np.array([beside_verdict(trace.ee[i], block[i], self.preposition, tol).success
                         for i in range(len(trace))], dtype=bool)

    def describe_end(self, world: Any, trace: Trace, tol: Tolerances) -> str:
        return beside_verdict(trace.ee[-1], trace.objects[self.obj][-1], self.preposition,
                              tol).reason

    def programs(self, progs: Programs) -> list[str]:
        word = SIDES[self.preposition][2]
        subtask = f"move to the {self.preposition} the {self.obj}"
        query = f"a point {OFFSET_CM}cm {'above' if word == 'top' else word + ' of'} the {self.obj}"
        gripper_composer(progs, subtask, {"affordance": query})
        progs.add("get_affordance_map", query, "affordance_map = get_empty_affordance_map()",
                  f"block = parse_query_obj('{self.obj}')",
                  f"x, y, z = point_beside(block, '{word}', {OFFSET_CM})",
                  "affordance_map[x, y, z] = 1", "ret_val = affordance_map")
        return [subtask]


@dataclass(frozen=True)
class AwayFrom(Step):
    """The end effector at least ``away_m`` from ``obj``'s faces ("move away from it"); the
    reference moves ``cm`` above the block."""

    obj: str
    cm: int = 15

    @property
    def label(self) -> str:
        return f"move away from the {self.obj}"

    def tracked(self) -> tuple[str, ...]:
        return (self.obj,)

    def held(self, world: Any, trace: Trace, tol: Tolerances) -> NDArray[np.bool_]:
        return block_distance(trace.ee, trace.objects[self.obj]) >= tol.away_m

    def describe_end(self, world: Any, trace: Trace, tol: Tolerances) -> str:
        d = float(block_distance(trace.ee[-1:], trace.objects[self.obj][-1:])[0])
        return f"the end effector ends {d * 100:.1f} cm from its faces (needs >= " \
               f"{tol.away_m * 100:.0f} cm)"

    def programs(self, progs: Programs) -> list[str]:
        return [point_above_programs(progs, self.obj, self.cm, self.label)]


@dataclass(frozen=True)
class AtPlaceKeepingAway(AtPlace):
    """:class:`AtPlace` with a constraint clause: "while staying at least [dist]cm from the
    [obj]" — the end effector–block-face distance over the step's span never below
    dist − ``min_dist_slack_m`` (as the task move_to_pos_min_distance judges it)."""

    obj: str = ""
    dist_cm: int = 5

    @property
    def label(self) -> str:
        return f"move to the {self.place} while staying at least {self.dist_cm}cm from the " \
               f"{self.obj}"

    def tracked(self) -> tuple[str, ...]:
        return (self.obj,)

    def constraint(self, world: Any, trace: Trace, span: slice, tol: Tolerances
                   ) -> tuple[bool, str]:
        closest = float(np.min(block_distance(trace.ee[span], trace.objects[self.obj][span])))
        need = self.dist_cm / 100 - tol.min_dist_slack_m
        return closest >= need, (f"closest {closest * 100:.1f} cm from the {self.obj}'s faces "
                                 f"(needs >= {need * 100:.1f})")

    def programs(self, progs: Programs) -> list[str]:
        place = get_place(self.place)
        subtask = self.label
        aff, avoid = place_query(place.name, HOVER_CM), f"at least {self.dist_cm}cm away from " \
            f"the {self.obj}"
        gripper_composer(progs, subtask, {"affordance": aff, "avoidance": avoid})
        progs.add("get_affordance_map", aff, *affordance_at_place(place, HOVER_CM))
        progs.add("get_avoidance_map", avoid, "avoidance_map = get_empty_avoidance_map()",
                  f"block = parse_query_obj('{self.obj}')",
                  f"set_voxel_by_radius(avoidance_map, block.position, "
                  f"{self.dist_cm + AVOID_MARGIN_CM}, 1)", "ret_val = avoidance_map")
        return [subtask]
