"""A multi-step instruction as a declarative benchmark unit: template, steps, layout.

A :class:`MultiStepTask` is a :class:`~voxposer.bench.task.BenchTask` whose template joins 2–3
steps ("hover 10cm over the [obj], then move to the [region]") and which declares them
(:meth:`MultiStepTask.steps`, :mod:`voxposer.bench.multistep.moves` /
:mod:`~voxposer.bench.multistep.objects`). From the steps it derives what a task needs:

* the check — every step held, in order (:func:`~voxposer.bench.multistep.order.judge_steps`);
* the reset — a start where no step already holds (besides the keep-clear discs);
* the objects the trace records — every step's;
* the reference programs — the planner runs the steps' sub-tasks in order, and the *wrong-order
  control* (:meth:`MultiStepTask.wrong_order`) the same programs with the steps reversed.

Subclasses register into the suite's own registry (:func:`suite_entries`), never into the
13-task registry (``registered_tasks``), so the 13-task benchmark is unchanged.
"""

from __future__ import annotations

from abc import abstractmethod
from typing import Any, ClassVar

from voxposer.bench.config import Tolerances
from voxposer.bench.multistep.order import judge_steps
from voxposer.bench.multistep.step import Step, planner_programs
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.trace import Trace, snapshot
from voxposer.errors import ConfigError

#: entry name → class, in declaration order.
_ENTRIES: dict[str, type[MultiStepTask]] = {}


def suite_entries() -> dict[str, type[MultiStepTask]]:
    """Every declared multi-step entry class, by name, in declaration order."""
    return dict(_ENTRIES)


class MultiStepTask(BenchTask, register=False):
    """Base of the multi-step suite's entries; a subclass declares ``name``, ``category``,
    ``template``, :meth:`steps` and :meth:`layout` (and ``keep_clear``/``compatible``)."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(register=False, **kwargs)
        name = cls.__dict__.get("name")
        if name is None:
            return
        if name in _ENTRIES and _ENTRIES[name].__qualname__ != cls.__qualname__:
            raise ConfigError(f"two multi-step entries are called {name!r}: "
                              f"{_ENTRIES[name].__qualname__} and {cls.__qualname__}")
        _ENTRIES[name] = cls

    #: multi-step entries are not rows of the paper's Table 4.
    paper_row: ClassVar[str] = ""

    @abstractmethod
    def steps(self, attrs: dict[str, str]) -> tuple[Step, ...]:
        """The instruction's steps for ``attrs``, in the order the instruction asks for."""

    def tracked(self, attrs: dict[str, str]) -> tuple[str, ...]:
        names: list[str] = []
        for step in self.steps(attrs):
            names += [n for n in step.tracked() if n not in names]
        return tuple(names)

    def reset_problem(self, world: Any, attrs: dict[str, str], tol: Tolerances) -> str | None:
        """The base class's problems (a distractor in a keep-clear disc), or a step that
        already holds at reset (it would be "done" before it is asked for)."""
        problem = super().reset_problem(world, attrs, tol)
        if problem is not None:
            return problem
        trace = snapshot(world, self.tracked(attrs))
        for k, step in enumerate(self.steps(attrs), 1):
            if bool(step.held(world, trace, tol)[0]):
                return f"step {k} ({step.label}) already holds at reset"
        return None

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        return judge_steps(self.steps(attrs), world, trace, tol)

    def reference(self, attrs: dict[str, str]) -> Programs:
        """The planner runs every step's sub-tasks in order; each step writes its programs."""
        return planner_programs(Programs(), self.instruction(attrs), self.steps(attrs))

    def wrong_order(self, attrs: dict[str, str]) -> Programs:
        """The wrong-order control: :meth:`reference` with the steps in reverse order (the
        instruction unchanged). The order check must fail it."""
        return planner_programs(Programs(), self.instruction(attrs), self.steps(attrs)[::-1])
