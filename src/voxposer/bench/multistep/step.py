"""One step of a multi-step instruction: a sub-goal whose condition is judged at every sample.

A :class:`Step` says, for every sample of an episode's :class:`~voxposer.bench.trace.Trace`,
whether its condition holds (``held``, shape (T,)) — "the end effector within 3 cm of the point
10 cm above the blue block", "the blue block resting at the back side of the table" — and writes
the reference programs of its sub-tasks. A step with a constraint clause ("while staying at
least 5cm from the blue block") also judges the samples between the previous step and its own
completion (:meth:`Step.constraint`). :mod:`voxposer.bench.multistep.order` turns the steps'
conditions into first-held times and the order check.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from voxposer.bench.config import Tolerances
from voxposer.bench.programs import Programs
from voxposer.bench.trace import Trace

#: The composer sub-task that returns the arm to its ready pose (shared by steps).
BACK_TO_DEFAULT = "back to default pose"


@dataclass(frozen=True)
class Step(ABC):
    """A sub-goal of a multi-step instruction (frozen: steps are values built from attributes).

    Subclasses declare ``label`` (how reasons name the step) and the objects their condition
    reads from the trace (:meth:`tracked`).
    """

    @property
    @abstractmethod
    def label(self) -> str:
        """The step in words ("hover 10cm over the blue block")."""

    #: whether the condition must still hold at the end of the episode (object states such as
    #: "the block at the corner": a later step must not undo it); end-effector poses need not.
    persists: ClassVar[bool] = False

    def tracked(self) -> tuple[str, ...]:
        """Objects whose positions the condition reads from the trace (default: none)."""
        return ()

    @abstractmethod
    def held(self, world: Any, trace: Trace, tol: Tolerances) -> NDArray[np.bool_]:
        """Whether the condition holds at each sample of ``trace``, shape (T,)."""

    @abstractmethod
    def describe_end(self, world: Any, trace: Trace, tol: Tolerances) -> str:
        """What the condition looks like at the end of the episode (for a failure reason)."""

    def constraint(self, world: Any, trace: Trace, span: slice, tol: Tolerances
                   ) -> tuple[bool, str]:
        """Whether the step's constraint clause held over the samples ``span`` (from the
        previous step's completion to the end of the first stretch this one's condition holds)
        and why; default: no clause, always holds."""
        return True, ""

    @abstractmethod
    def programs(self, progs: Programs) -> list[str]:
        """Add this step's composer and map programs to ``progs``; returns its composer
        sub-tasks in order (the planner's lines)."""


def back_to_default(progs: Programs) -> str:
    """Record the composer program of :data:`BACK_TO_DEFAULT` and return that sub-task."""
    progs.add("composer", BACK_TO_DEFAULT, "reset_to_default_pose()")
    return BACK_TO_DEFAULT


def planner_programs(progs: Programs, instruction: str, steps: tuple[Step, ...]) -> Programs:
    """The planner's program for ``instruction``: every step's sub-tasks, in ``steps`` order."""
    subtasks: list[str] = []
    for step in steps:
        subtasks += step.programs(progs)
    return progs.add("planner", instruction, *(f"composer('{s}')" for s in subtasks))
