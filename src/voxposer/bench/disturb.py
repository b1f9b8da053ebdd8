"""``--disturb``: the paper's disturbances (App. A.4, Table 1) in benchmark episodes.

A disturbed episode is the static episode (same task, split, seed, hence the same start) run
with a :class:`~voxposer.control.disturbance_schedule.Disturber`: a push of the robot, a
displacement of a block and — where the entity of interest is an object or a part — reverting
progress, on the schedule of :mod:`voxposer.control.disturbance_schedule` (VoxPoser: fractions
of sub-task progress; the LLM + Primitives baseline, which never replans: sim-time offsets).

What the bench tells the disturber: the task-relevant blocks (``task.tracked(attrs)``: the blocks
the instruction names; a gripper sub-task's displacement moves the first of them), and for the
sim-time schedule the entity of interest of the task's reference programs (the ``movable`` of
their first ``execute``), since the baseline names none.

Path-based checks (push along a line, stay on a region) see a displaced block's jump in the
episode trace; the disturbance is recorded with the episode, so such failures can be told apart.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from voxposer.bench.task import BenchTask
from voxposer.control.disturbance_schedule import DisturbanceSchedule, Disturber

_MOVABLE = re.compile(r"movable\s*=\s*parse_query_obj\('([^']+)'\)")


def reference_entity(task: BenchTask, attrs: dict[str, str]) -> str:
    """The entity of interest of ``task``'s reference programs for ``attrs``: the first
    ``movable`` a composer program parses ("gripper" when there is none)."""
    for entry in task.reference(attrs).entries():
        if entry["lmp"] == "composer":
            found = _MOVABLE.search(entry["responses"][0])
            if found:
                return found.group(1)
    return "gripper"


class EpisodeDisturbance:
    """Builds an episode's disturber (a ``Method.run`` ``make_disturber``) and keeps it, so its
    record survives a method that fails.

    Args:
        world: the episode's world.
        task, attrs: the episode's task and attributes.
    """

    def __init__(self, world: Any, task: BenchTask, attrs: dict[str, str]) -> None:
        self.world = world
        self.relevant = tuple(n for n in task.tracked(attrs) if n.endswith(" block"))
        self.entity = reference_entity(task, attrs)
        self.disturber: Disturber | None = None

    def __call__(self, rng: np.random.Generator, reach_tolerance_m: float) -> Disturber:
        """A disturber drawing from ``rng``, quiet within ``reach_tolerance_m`` [m] of a target."""
        schedule = DisturbanceSchedule(reach_tolerance_m=reach_tolerance_m)
        self.disturber = Disturber(self.world, rng, self.relevant, self.entity, schedule)
        return self.disturber

    @property
    def applied(self) -> list[dict[str, Any]]:
        """What was applied, in order (empty before the method ran)."""
        return [] if self.disturber is None else list(self.disturber.applied)
