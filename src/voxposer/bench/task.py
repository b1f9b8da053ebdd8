"""One benchmark task as a small declarative unit: template, attributes, reset, check, programs.

A task (paper App. A.5) is a templated instruction ("push the [obj] to the [pos]") whose slots are
filled from the seen/unseen attribute lists, a scene layout built from the attributes plus
distractors, a success check over the final world state and the episode's :class:`Trace`, and
the *reference programs* a correct LLM would write (replayed by the ReplayBackend).

:func:`reset_episode` draws the attributes and resets the world until the task is neither
complete nor infeasible (targets reachable, distractors clear of the places the task needs).
"""

from __future__ import annotations

import math
import re
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal, NamedTuple

import numpy as np

from voxposer.bench.attributes import Split, check_split, values
from voxposer.bench.config import Tolerances
from voxposer.bench.programs import Programs
from voxposer.bench.trace import Trace, snapshot
from voxposer.envs.layout import SceneLayout
from voxposer.errors import ConfigError, LayoutError, VoxPoserError

Category = Literal["Object Interactions", "Spatial Composition"]
_SLOT = re.compile(r"\[(\w+)\]")
_RESET_ATTEMPTS = 60


class Verdict(NamedTuple):
    """A success check's answer: success, a sentence saying why, and the measured numbers."""

    success: bool
    reason: str
    metrics: dict[str, float]


class ResetError(VoxPoserError):
    """No valid initial state was found for an episode."""


@dataclass(frozen=True)
class EpisodeSetup:
    """What :func:`reset_episode` chose.

    Attributes:
        task, split, seed: identify the episode.
        attributes: slot → value ("obj" → "blue block").
        instruction: the filled-in template.
        layout: the scene layout the world was reset with.
        rng: the generator after the reset (for the executor's randomness).
    """

    task: str
    split: Split
    seed: int
    attributes: dict[str, str]
    instruction: str
    layout: SceneLayout
    rng: np.random.Generator = field(repr=False)


#: every concrete task class, by name, in the order their modules were imported.
_REGISTERED: dict[str, type[BenchTask]] = {}


def registered_tasks() -> dict[str, type[BenchTask]]:
    """Every task class that declared itself (a concrete subclass of :class:`BenchTask` with a
    ``name``), by name; :mod:`voxposer.bench.tasks` imports every task module first."""
    return dict(_REGISTERED)


class BenchTask(ABC):
    """Base of the 13 tasks; subclasses are small declarations (see ``tasks/``).

    A subclass registers itself when its module is imported: adding a task is adding one module
    to ``voxposer/bench/tasks/`` (its Gymnasium id, its parametrised test and ``--tasks`` follow).
    """

    def __init_subclass__(cls, register: bool = True, **kwargs: Any) -> None:
        """Register a concrete subclass with a ``name``; ``register=False`` keeps it out of the
        13-task registry (the multi-step suite, :mod:`voxposer.bench.multistep`, keeps its own)."""
        super().__init_subclass__(**kwargs)
        name = cls.__dict__.get("name")
        # (ABCMeta computes __abstractmethods__ only after this hook: look at the methods)
        abstract = any(getattr(getattr(cls, m, None), "__isabstractmethod__", False)
                       for m in ("layout", "check", "reference"))
        if name is None or abstract or not register:
            return
        if name in _REGISTERED and _REGISTERED[name].__qualname__ != cls.__qualname__:
            raise ConfigError(f"two benchmark tasks are called {name!r}: "
                              f"{_REGISTERED[name].__qualname__} and {cls.__qualname__}")
        _REGISTERED[name] = cls

    name: ClassVar[str]
    category: ClassVar[Category]
    #: the paper's template, slots in brackets: "push the [obj] to the [pos]".
    template: ClassVar[str]
    #: the row label of Table 4 (the paper writes "from the obj" in one template).
    paper_row: ClassVar[str]

    @property
    def slots(self) -> tuple[str, ...]:
        """The attribute slots of the template, in order."""
        return tuple(_SLOT.findall(self.template))

    def instruction(self, attrs: dict[str, str]) -> str:
        """The template filled with ``attrs``."""
        return _SLOT.sub(lambda m: attrs[m.group(1)], self.template)

    # ---------------------------------------------------------------- attributes and reset
    def sample_attributes(self, rng: np.random.Generator, split: Split) -> dict[str, str]:
        """One value per slot from ``split``'s lists (``obstacle`` differs from ``obj``);
        combinations :meth:`compatible` rejects are redrawn."""
        for _ in range(200):
            attrs: dict[str, str] = {}
            for slot in self.slots:
                options = [v for v in values(slot, split) if v not in attrs.values()]
                attrs[slot] = str(options[int(rng.integers(len(options)))])
            if self.compatible(attrs):
                return attrs
        raise ResetError(f"{self.name}: no compatible attribute combination in {split}")

    def compatible(self, attrs: dict[str, str]) -> bool:
        """Whether an attribute combination makes a feasible task (default: all do)."""
        return True

    @abstractmethod
    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        """The scene for ``attrs``: task objects placed by hand (from ``rng``) + distractors."""

    def tracked(self, attrs: dict[str, str]) -> tuple[str, ...]:
        """Objects whose positions the episode trace records (default: the named blocks)."""
        return tuple(attrs[s] for s in ("obj", "obstacle") if s in attrs)

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        """(x, y) [m] and radius [m] that distractor blocks must keep clear of (targets, paths),
        given the reset world (task objects already placed)."""
        return []

    def reset_problem(self, world: Any, attrs: dict[str, str], tol: Tolerances) -> str | None:
        """Why the reset state is not a valid start (None when valid): task already complete,
        or a distractor in the way."""
        named = set(self.tracked(attrs))
        for xy, radius in self.keep_clear(world, attrs):
            for name in world.object_names:
                if name.endswith(" block") and name not in named:
                    d = math.dist(world.object_position(name)[:2], xy)
                    if d < radius:
                        return f"{name} is {d:.2f} m from {xy}, inside the {radius} m keep-clear"
        verdict = self.check(world, snapshot(world, self.tracked(attrs)), attrs, tol)
        return "the task is already complete at reset" if verdict.success else None

    # ------------------------------------------------------------------------ success
    @abstractmethod
    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        """Success of the episode from the final world state and its trace."""

    # ------------------------------------------------------------------------ programs
    @abstractmethod
    def reference(self, attrs: dict[str, str]) -> Programs:
        """What a correct LLM writes for VoxPoser's LMPs (planner, composer, maps, objects)."""

    def primitives_reference(self, attrs: dict[str, str]) -> Programs | None:
        """What a correct LLM writes for the LLM + Primitives baseline (None: not provided)."""
        return None

    #: the constraint clause the instruction carries ("avoidance map", "velocity map", …);
    #: None for tasks without one. Constrained tasks declare :meth:`blind`.
    constraint: ClassVar[str | None] = None

    def blind(self, attrs: dict[str, str]) -> Programs | None:
        """The constraint-blind control: :meth:`reference` with the constraint's map removed and
        nothing else changed (None for tasks without a constraint). A layout tests its
        constraint only if this control fails."""
        return None


def episode_rng(task: str, split: str, seed: int) -> np.random.Generator:
    """The episode's only source of randomness, from (task, split, seed)."""
    key = [ord(c) for c in f"{task}/{split}"]
    return np.random.default_rng([seed, *key])


def reset_episode(task: BenchTask, world: Any, split: str, seed: int,
                  tol: Tolerances | None = None) -> EpisodeSetup:
    """Draw attributes and reset ``world`` to a valid start; same (task, split, seed) → same.

    Raises:
        ResetError: no valid start after many layouts (the message says the last problem).
    """
    tol = tol or Tolerances()
    split = check_split(split)
    rng = episode_rng(task.name, split, seed)
    attrs = task.sample_attributes(rng, split)
    problem = "no layout tried"
    for _ in range(_RESET_ATTEMPTS):
        try:
            layout = task.layout(rng, attrs)
            world.reset(rng, layout)
        except LayoutError as err:
            problem = str(err)
            continue
        problem = task.reset_problem(world, attrs, tol) or ""
        if not problem:
            return EpisodeSetup(task.name, split, seed, attrs, task.instruction(attrs), layout,
                                rng)
    raise ResetError(f"{task.name} ({split}, seed {seed}, {attrs}): no valid start; last: "
                     f"{problem}")
