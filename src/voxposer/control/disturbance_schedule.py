"""The paper's disturbances (App. A.4, Table 1) on a schedule relative to each motion.

Three kinds, each applied at most once per episode, by calling the world's methods
(:mod:`voxposer.envs.disturbances`; this module never imports the world):

1. ``push_robot`` — a random force on a robot link;
2. ``displace_object`` — move a block elsewhere: the entity of interest if it is a block, else a
   task-relevant block (for gripper sub-tasks, the block the instruction names), else a
   distractor;
3. ``revert_progress`` — only where the entity of interest is an object or an object part: a
   drawer is pulled open again by a force (``pull_drawer``: physics, so a hand in front of it is
   pushed back rather than passed through), a pushed block is put back toward where the
   sub-task started (``return_object``).

An object in the closed hand is neither displaced nor reverted (it would be pulled out of the
fingers); a kind with nothing to act on, or that the world refuses (no free spot on the table),
waits for a later replan.

**The schedule: fractions of sub-task progress** (:meth:`Disturber.on_replan`, driven by the
executor's ``on_replan`` callback). The progress of the current sub-task (one ``execute`` call)
at a replan is the fraction of the initial entity-to-target distance covered::

    p = |x − x₀| / d₀

x: the entity's position at this replan (``plan.cost_map.start``, [m]); x₀, d₀: its position
and its distance to the target (``result.final_distance`` [m]) at the sub-task's first replan.
Each kind fires at the first replan with p ≥ its fraction (default: push 0.2, revert 0.4,
displacement 0.6) — at most one kind per replan, never on a replan where the entity is already
within ``reach_tolerance_m`` of its target (the executor stops there without observing again,
so the disturbance would go unanswered), and a kind not yet fired carries over to later
sub-tasks. Progress rather than
fixed times: motions last from 2 s (moving the hand to a region) to 20 s (pushing a block), so
fixed times would fall after the short motions ended and only at the start of the long ones;
progress hits every motion at the same stage. (A drawer pushed "25 cm in" keeps its target
25 cm ahead; x still advances with the handle, so p is the fraction of those 25 cm covered.)

**Sim-time schedule** (:meth:`Disturber.attach`), for methods without replans (the LLM +
Primitives baseline): a world step callback fires each kind at ``times_s`` simulated seconds
(default: push 1 s, revert 2 s, displacement 3 s) after the first physics step, with the entity
given to the disturber.

Randomness comes from the generator passed in (spawn it from the episode's). What was applied
is a list of JSON-ready records (:func:`applied_record`): the kind, the object disturbed, its
position or opening before and after, the force, and when.
"""

from __future__ import annotations

import logging
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any, Final, Protocol

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError, VoxPoserError
from voxposer.perception.names import is_end_effector

log = logging.getLogger(__name__)

#: the kinds, in schedule order (the names of the world's methods, except the block revert).
KINDS: Final = ("push_robot", "displace_object", "revert_progress")
#: an object this close to the closed hand [m] counts as held (``ExecutorConfig.carry_radius_m``)
#: when the fingers closed on something, at least this far apart [m].
HELD_RADIUS_M: Final = 0.08
HELD_OPENING_M: Final = 0.01


class DisturbableWorld(Protocol):
    """What the disturber needs of a world (:class:`voxposer.envs.TabletopWorld` has it)."""

    data: Any
    step_callbacks: list[Any]

    @property
    def object_names(self) -> tuple[str, ...]: ...
    def get_gripper_state(self) -> float: ...
    def gripper_opening(self) -> float: ...
    def get_ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
    def object_position(self, name: str) -> NDArray[np.float64]: ...
    def push_robot(self, rng: np.random.Generator) -> Any: ...
    def displace_object(self, rng: np.random.Generator, name: str | None = None) -> Any: ...
    def pull_drawer(self, rng: np.random.Generator, drawer: str | None = None) -> Any: ...
    def return_object(self, rng: np.random.Generator, name: str, to: Any) -> Any: ...


@dataclass(frozen=True)
class DisturbanceSchedule:
    """When each kind fires.

    Attributes:
        progress: sub-task progress fraction per kind of :data:`KINDS` (see module docs), each
            in (0, 1]; default: the push at 0.2, the revert at 0.4 (while the drawer is still
            being closed), the displacement at 0.6.
        times_s: simulated seconds after motion starts per kind of :data:`KINDS` [s] (the
            sim-time schedule; default push 1 s, displacement 3 s, revert 2 s: the order of
            ``progress``).
        reach_tolerance_m: no disturbance on a replan within this distance of the target [m]
            (``ExecutorConfig.reach_tolerance_m``).
    """

    progress: tuple[float, float, float] = (0.2, 0.6, 0.4)
    times_s: tuple[float, float, float] = (1.0, 3.0, 2.0)
    reach_tolerance_m: float = 0.02

    def __post_init__(self) -> None:
        for name in ("progress", "times_s"):
            values = getattr(self, name)
            if len(values) != len(KINDS) or any(not v > 0 for v in values):
                raise ConfigError(f"DisturbanceSchedule.{name} must hold {len(KINDS)} positive "
                                  f"values (for {', '.join(KINDS)}); got {values!r}")
        if any(v > 1 for v in self.progress):
            raise ConfigError(f"DisturbanceSchedule.progress fractions must be <= 1; got "
                              f"{self.progress!r}")
        if not self.reach_tolerance_m >= 0:
            raise ConfigError(f"DisturbanceSchedule.reach_tolerance_m must be >= 0; got "
                              f"{self.reach_tolerance_m!r}")


def _vector(value: Any) -> list[float]:
    return [round(float(v), 4) + 0.0 for v in np.atleast_1d(np.asarray(value, dtype=np.float64))]


def applied_record(kind: str, target: str, entity: str, sim_time_s: float,
                   progress: float | None, done: Any) -> dict[str, Any]:
    """One entry of :attr:`Disturber.applied`: ``kind`` applied to ``target`` and what the world
    returned (a :class:`~voxposer.envs.disturbances.Disturbance`: target, before, after,
    duration).

    Keys: ``kind`` (of :data:`KINDS`), ``object`` ("robot", a block, a drawer), ``entity`` (the
    sub-task's entity of interest), ``sim_time_s`` [s], ``progress`` (None on the sim-time
    schedule), ``link`` (the robot link a push hit, else None), ``position_before_m`` /
    ``position_after_m`` (a block's position [m], (3,); a push: the link's before, after None),
    ``opening_before_m`` / ``opening_after_m`` (a drawer's opening [m]; after a pull: None, physics
    decides), ``force_n`` (the force of a push or pull [N], (3,), else None), ``duration_s``;
    and, as recorded before these keys existed, ``target``, ``before``, ``after``.
    """
    target = str(getattr(done, "target", target))
    before, after = _vector(getattr(done, "before", ())), _vector(getattr(done, "after", ()))
    duration = float(getattr(done, "duration", 0.0))
    entry: dict[str, Any] = {
        "kind": kind, "object": target, "entity": entity, "sim_time_s": round(sim_time_s, 3),
        "progress": None if progress is None else round(progress, 3), "link": None,
        "position_before_m": None, "position_after_m": None, "opening_before_m": None,
        "opening_after_m": None, "force_n": None, "duration_s": duration}
    if kind == "push_robot":
        entry.update(object="robot", link=target, position_before_m=before, force_n=after)
    elif "drawer" in target:
        forced = duration > 0  # a pull: "after" is its force
        entry.update(opening_before_m=before[0] if before else None,
                     opening_after_m=None if forced or not after else after[0],
                     force_n=after if forced else None)
    else:
        entry.update(position_before_m=before, position_after_m=after)
    return {**entry, "target": target, "before": before, "after": after}


@dataclass
class Disturber:
    """Applies the scheduled disturbances to one episode (see module docs).

    Attributes:
        world: the world disturbed.
        rng: the disturbances' only randomness.
        relevant: the task-relevant blocks, most relevant first ("blue block").
        entity: the entity of interest for the sim-time schedule (None: the end effector).
        schedule: when each kind fires.
        applied: what was applied, in order, as JSON-ready records (:func:`applied_record`).
    """

    world: DisturbableWorld
    rng: np.random.Generator
    relevant: Sequence[str] = ()
    entity: str | None = None
    schedule: DisturbanceSchedule = field(default_factory=DisturbanceSchedule)
    applied: list[dict[str, Any]] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._pending = sorted(zip(KINDS, self.schedule.progress, self.schedule.times_s,
                                   strict=True), key=lambda k: k[1])
        self._subtask: tuple[int, NDArray[np.float64], float] | None = None  # id, x₀, d₀
        self._t0: float | None = None
        self._start: NDArray[np.float64] | None = None

    # ------------------------------------------------------------ progress schedule
    def __call__(self, result: Any, plan: Any) -> None:
        """``on_replan`` callback of the closed-loop executor."""
        self.on_replan(result, plan)

    def on_replan(self, result: Any, plan: Any) -> None:
        """Fire the first pending, applicable kind whose progress fraction the current
        sub-task has reached (``result``: its ExecutionResult so far; ``plan``: this replan's)."""
        x = np.asarray(plan.cost_map.start, dtype=np.float64)
        distance = float(result.final_distance)
        if self._subtask is None or self._subtask[0] != id(result) or result.replans <= 1:
            self._subtask = (id(result), x, distance)
        _, x0, d0 = self._subtask
        if d0 <= self.schedule.reach_tolerance_m or distance <= self.schedule.reach_tolerance_m:
            return
        progress = float(np.linalg.norm(x - x0)) / d0
        for item in self._pending:
            kind, fraction = item[0], item[1]
            if progress >= fraction and self._fire(kind, str(result.entity), x0, progress):
                self._pending.remove(item)
                return

    # ------------------------------------------------------------ sim-time schedule
    @contextmanager
    def attach(self) -> Iterator[Disturber]:
        """Run the sim-time schedule while inside: a world step callback fires each kind
        ``times_s`` simulated seconds after the first step inside the block."""
        self.world.step_callbacks.append(self._on_step)
        try:
            yield self
        finally:
            if self._on_step in self.world.step_callbacks:
                self.world.step_callbacks.remove(self._on_step)

    def _on_step(self, world: Any) -> None:
        now = float(world.data.time)
        entity = self.entity or "gripper"
        if self._t0 is None:
            self._t0 = now
            if not is_end_effector(entity) and entity in world.object_names:
                self._start = np.asarray(world.object_position(entity), dtype=np.float64)
        start = self._start if self._start is not None else np.zeros(3)
        for item in self._pending:
            if now - self._t0 >= item[2] and self._fire(item[0], entity, start, None):
                self._pending.remove(item)
                return

    # ------------------------------------------------------------------ applying
    def _fire(self, kind: str, entity: str, start: NDArray[np.float64],
              progress: float | None) -> bool:
        """Apply ``kind``; False when it has nothing to act on now or the world refused (it
        stays pending)."""
        now = float(self.world.data.time)
        target = self._target(kind, entity)
        if target is None:
            return False
        try:
            done = self._apply(kind, target, start)
        except VoxPoserError as err:  # e.g. no free spot on the table: try again later
            log.info("disturbance %s of %s refused: %s", kind, target, err)
            return False
        entry = applied_record(kind, target, entity, now, progress, done)
        log.info("disturbance %s of %s at t=%.2f s", kind, entry["target"], now)
        self.applied.append(entry)
        return True

    def _target(self, kind: str, entity: str) -> str | None:
        """What ``kind`` acts on now ("robot", a block, "top drawer"), or None."""
        if kind == "push_robot":
            return "robot"
        if kind == "revert_progress":
            if "drawer" in entity:
                return entity.removesuffix(" handle")
            return entity if self._movable_block(entity) else None
        candidates = [entity, *self.relevant]
        for name in candidates:
            if self._movable_block(name):
                return name
        others = sorted(n for n in self.world.object_names
                        if self._movable_block(n) and n not in candidates)
        return str(others[int(self.rng.integers(len(others)))]) if others else None

    def _movable_block(self, name: str) -> bool:
        """A block of the scene that is not in the hand (held: the hand closed on something,
        fingers at least ``HELD_OPENING_M`` apart, within ``HELD_RADIUS_M`` of the block)."""
        if not name.endswith(" block") or name not in self.world.object_names:
            return False
        if self.world.get_gripper_state() < 0.5 or self.world.gripper_opening() < HELD_OPENING_M:
            return True
        hand = np.asarray(self.world.get_ee_pose()[0], dtype=np.float64)
        return float(np.linalg.norm(self.world.object_position(name) - hand)) > HELD_RADIUS_M

    def _apply(self, kind: str, target: str, start: NDArray[np.float64]) -> Any:
        if kind == "push_robot":
            return self.world.push_robot(self.rng)
        if kind == "displace_object":
            return self.world.displace_object(self.rng, target)
        if "drawer" in target:
            return self.world.pull_drawer(self.rng, target)
        return self.world.return_object(self.rng, target, start)


__all__ = ["HELD_OPENING_M", "HELD_RADIUS_M", "KINDS", "DisturbableWorld", "DisturbanceSchedule",
           "Disturber", "applied_record"]
