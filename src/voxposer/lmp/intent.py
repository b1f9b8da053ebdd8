"""Intent checks (beyond the paper): post-conditions the planner states after its sub-tasks.

The planner's code may follow a ``composer(...)`` call with ``expect(<condition>)``, e.g.::

    composer('push the pink block to the right side of the table')
    expect(on('pink block', 'table', 'right side'), moved('pink block', toward='right'))

Each condition is evaluated right after the sub-task it follows, on what perception sees then
(and, for :meth:`IntentChecks.away`, :meth:`~IntentChecks.passed_on` and
:meth:`~IntentChecks.speed`, the path the sub-task executed). A condition is a
:class:`Condition`: whether it held and what was measured. ``expect`` records every condition
as an :class:`IntentResult`; :meth:`IntentChecks.verdict` says whether all held. Nothing here
stops the plan: a false post-condition is reported after the run ("success" of ``voxposer run``
needs every sub-task's target reached *and* every stated post-condition true).

Distances are in centimetres as the instruction states them; "gripper" (and its synonyms)
means the end effector. Measured to an object, a distance is from the point (the end effector,
or the other object's centre) to the nearest face of the object's box (0 inside it).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from voxposer import catalog
from voxposer.errors import ConfigError, VoxPoserError
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.intent_conditions import Condition, IntentResult, call_text
from voxposer.lmp.intent_motion import AWAY_CM, NEAR_CM, PathConditions
from voxposer.lmp.intent_paths import box_gap, densify, face_shift
from voxposer.lmp.sides import parse_side
from voxposer.perception.names import is_end_effector, match_name, normalize_name

#: default displacement [cm] that counts as "moved".
MOVED_CM: Final = 2.0
#: how far [cm] outside an object's footprint something still counts as "above" it.
ABOVE_MARGIN_CM: Final = 3.0
#: how close [cm] an object's centre must be to the end effector to be "held".
HOLD_CM: Final = 8.0
#: "on the front side of" an object: level with it within this [cm] across that side, and
#: at most this far [cm] from it.
BESIDE_LATERAL_CM: Final = 4.0
BESIDE_MAX_CM: Final = 15.0
#: the names the planner's code sees.
HELPERS: Final = ("expect", "moved", "near", "on", "above", "away", "far", "passed_on",
                  "speed", "holding", "released", "along")


class IntentChecks(PathConditions):
    """The post-condition helpers of the planner's code, bound to a scene's API.

    The runtime calls :meth:`begin_subtask` before every ``composer`` call (positions are
    remembered then) and :meth:`add_execution` with every executed ``execute`` result.
    """

    def __init__(self, api: LMPAPI) -> None:
        self.api = api
        self.results: list[IntentResult] = []
        self._subtask = ""
        #: descriptions parse_query_obj resolved → scene names (:meth:`alias`)
        self._aliases: dict[str, str] = {}
        self._before: dict[str, NDArray[np.float64]] = {}
        self._before_box: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}
        #: every visible object's half-extent [m] (3,) when the sub-task began (a block
        #: pushed and turned since has a larger axis-aligned box)
        self._start_half: dict[str, NDArray[np.float64]] = {}
        #: every visible object's box (lo, hi) [m] when the sub-task began (an obstacle
        #: pushed aside was where the other came close to it)
        self._start_box: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}
        self._paths: dict[str, list[NDArray[np.float64]]] = {}
        self._timed: list[tuple[NDArray[np.float64], NDArray[np.float64]]] = []
        #: the end effector's speed at speed scale 1 [m/s] (the robot's; None: unknown, so
        #: ``speed`` conditions cannot be evaluated)
        self.ee_speed: float | None = None

    # --------------------------------------------------------------- runtime hooks
    def begin_subtask(self, subtask: str) -> None:
        """Remember every visible object's centre [m] before ``subtask`` runs."""
        self._subtask = str(subtask)
        self._paths, self._timed = {}, []
        before: dict[str, NDArray[np.float64]] = {"gripper": self._ee()}
        self._before_box, self._start_half, self._start_box = {}, {}, {}
        for name in self.api.scene.object_names:
            if is_end_effector(name):
                continue
            try:
                found = self.api.detect(name)
            except VoxPoserError:  # not visible now
                continue
            before[name] = found.position_world.astype(np.float64)
            lo, hi = (np.asarray(v, float) for v in found.aabb_world)
            self._start_half[name] = (hi - lo) / 2.0
            self._start_box[name] = (lo, hi)
            if _sliding(name):
                self._before_box[name] = (lo, hi)
        self._before = before

    def add_execution(self, outcome: Any) -> None:
        """Keep the paths [m] an ``execute`` call took: the end effector's ``trace`` and the
        entity's ``entity_path`` (shape (N, 3); one sample per replan, so filled in along the
        straight segments between them: :func:`~voxposer.lmp.intent_paths.densify`), when the
        executor reports them."""
        trace = getattr(outcome, "trace", None)
        if trace is not None and len(trace):
            ee_path = np.asarray(trace, float).reshape(-1, 3)
            self._paths.setdefault("gripper", []).append(ee_path)
            times = np.asarray(getattr(outcome, "trace_time", []), float).reshape(-1)
            if len(times) == len(ee_path):
                self._timed.append((ee_path, times))
        entity, path = getattr(outcome, "entity", None), getattr(outcome, "entity_path", None)
        if entity and path is not None and len(path):
            key = "gripper" if is_end_effector(str(entity)) else str(entity)
            self._paths.setdefault(key, []).append(densify(path))

    def verdict(self) -> bool | None:
        """True when every evaluated condition held, False when one did not, None when the
        planner stated none that could be evaluated."""
        checked = [r for r in self.results if not r.error]
        if not checked:
            return None
        return all(r.held for r in checked)

    def failed(self) -> list[IntentResult]:
        """The evaluated conditions that did not hold, in order."""
        return [r for r in self.results if not r.error and not r.held]

    def namespace(self, wrap: Callable[[Callable[..., Any]], Callable[..., Any]]
                  ) -> dict[str, Callable[..., Any]]:
        """Name → helper for the planner's code; ``wrap`` adapts each (e.g. lifts the
        sandbox's time limit while it perceives). A helper never raises into the plan: a
        condition it cannot evaluate is recorded as such (``error``) and not counted."""
        return {name: wrap(self._guarded(name)) for name in HELPERS}

    def _guarded(self, name: str) -> Callable[..., Any]:
        fn = getattr(self, name)

        def call(*args: Any, **kwargs: Any) -> Any:
            try:
                return fn(*args, **kwargs)
            except Exception as exc:  # untrusted arguments: report, never break the plan
                text = call_text(name, *args, **kwargs)
                measured = f"could not evaluate: {type(exc).__name__}: {exc}"
                if name == "expect":
                    self.results.append(IntentResult(self._subtask, text, False, measured, True))
                    return False
                return Condition(text, False, measured, error=True)
        call.__name__ = name
        return call

    # --------------------------------------------------------------- the helpers
    def expect(self, *conditions: Any) -> bool:
        """Record ``conditions`` (each a :class:`Condition`) against the last sub-task; True
        when all held."""
        if not conditions:
            raise ConfigError("expect() needs at least one condition, e.g. "
                              "expect(moved('blue block', toward='left'))")
        for cond in conditions:
            if not isinstance(cond, Condition):
                raise ConfigError(f"expect() takes conditions from moved/near/on/above/away/"
                                  f"far/passed_on/speed/holding/released/along; got {type(cond).__name__} {cond!r}")
            self.results.append(IntentResult(self._subtask, cond.text, bool(cond.held),
                                             cond.measured, bool(cond.error)))
        return all(bool(c.held) for c in conditions)

    def moved(self, obj: str, toward: str | None = None, cm: float = MOVED_CM) -> Condition:
        """``obj``'s centre moved at least ``cm`` [cm] since the sub-task began (along
        ``toward``, a side phrase such as "left" or "back right", when given); a drawer or a
        handle by its box's faces (:func:`~voxposer.lmp.intent_paths.face_shift`)."""
        name = self._name(obj)
        text = call_text("moved", obj, toward=toward, cm=cm)
        if name not in self._before:
            return Condition(text, False, f"the {name} was not seen before the sub-task")
        if name in self._before_box:  # a drawer: by its faces (its body slides out of view)
            delta = face_shift(self._before_box[name], self._aabb(name)) * 100.0
        else:
            delta = (self._centre(name) - self._before[name]) * 100.0
        if toward is None:
            dist = float(np.linalg.norm(delta))
            return Condition(text, dist >= cm, f"moved {dist:.1f} cm")
        signs = parse_side(toward)
        if not signs:
            raise ConfigError(f"moved(): toward={toward!r} names no direction; use words such "
                              "as 'left', 'back', 'up', 'front right'")
        unit = np.zeros(3)
        for axis, sign in signs.items():
            unit[axis] = sign
        along = float(delta @ (unit / np.linalg.norm(unit)))
        return Condition(text, along >= cm, f"moved {along:.1f} cm toward {toward} "
                                            f"({np.linalg.norm(delta):.1f} cm in all)")

    def near(self, obj: str, target: str, cm: float = NEAR_CM) -> Condition:
        """``obj`` (its centre, or the end effector) is within ``cm`` [cm] of ``target``'s box."""
        name, other = self._name(obj), self._name(target)
        dist = 100.0 * self._box_distance(self._centre(name)[None], other).min()
        return Condition(call_text("near", obj, target, cm=cm), dist <= cm,
                         f"{dist:.1f} cm from the {other}")

    def on(self, obj: str, target: str, where: str = "center") -> Condition:
        """``obj``'s centre lies over the ``where`` part of the table ("right side", "back left
        corner": the places the API's ``region_mask`` gives); beside another object, it lies
        on that side of it ("front side": beyond its front face, level with it ±4 cm, within
        15 cm of it)."""
        name, other = self._name(obj), self._name(target)
        centre = self._centre(name)
        text = call_text("on", obj, target, where)
        if other != "table":
            return self._beside(text, name, other, where, centre)
        grid = self.api.grid
        if not bool(grid.contains(centre)):
            return Condition(text, False, f"the {name} is outside the workspace")
        mask = self.api.region_mask(other, where)
        i, j, k = (int(v) for v in grid.world_to_voxel(centre))
        held = bool(mask[i, j, k])
        return Condition(text, held, f"the {name} at {np.round(centre[:2], 3).tolist()} m is "
                                     f"{'' if held else 'not '}over the {where}")

    def _beside(self, text: str, name: str, other: str, where: str,
                centre: NDArray[np.float64]) -> Condition:
        """``on`` for an object other than the table: ``name`` on the ``where`` side of it."""
        signs = parse_side(where, name=other)
        lo, hi = self._aabb(other)
        slack, lateral = 0.01, BESIDE_LATERAL_CM / 100.0
        beyond = all(sign * (centre[axis] - (hi[axis] if sign > 0 else lo[axis])) >= -slack
                     for axis, sign in signs.items())
        level = all(lo[a] - lateral <= centre[a] <= hi[a] + lateral
                    for a in (0, 1) if a not in signs)
        dist = 100.0 * float(self._box_distance(centre[None], other)[0])
        held = beyond and level and dist <= BESIDE_MAX_CM
        return Condition(text, held, f"the {name} is {dist:.1f} cm from the {other}, "
                                     f"{'' if beyond else 'not '}beyond its {where} face, "
                                     f"{'' if level else 'not '}level with it")

    def above(self, obj: str, target: str, cm: float | None = None) -> Condition:
        """``obj`` is over ``target``'s footprint (±3 cm) and higher than its top (by about
        ``cm`` [cm], ±3 cm, when given)."""
        name, other = self._name(obj), self._name(target)
        centre, (lo, hi) = self._centre(name), self._aabb(other)
        margin = ABOVE_MARGIN_CM / 100.0
        over = bool(np.all(centre[:2] >= lo[:2] - margin) and np.all(centre[:2] <= hi[:2] + margin))
        height = 100.0 * (centre[2] - hi[2])
        high = height > 0 if cm is None else abs(height - cm) <= ABOVE_MARGIN_CM
        return Condition(call_text("above", obj, target, cm=cm), over and high,
                         f"{height:.1f} cm above the {other}'s top, "
                         f"{'over' if over else 'not over'} it")

    def holding(self, obj: str) -> Condition:
        """The gripper is closed with ``obj``'s centre within 8 cm of the end effector."""
        name = self._name(obj)
        closed = float(self.api.scene.gripper_state()) > 0.5
        dist = 100.0 * float(np.linalg.norm(self._centre(name) - self._ee()))
        return Condition(call_text("holding", obj), closed and dist <= HOLD_CM,
                         f"gripper {'closed' if closed else 'open'}, the {name} {dist:.1f} cm "
                         "from it")

    def released(self, obj: str) -> Condition:
        """The hand let ``obj`` go: the gripper is open, or ``obj``'s centre is more than
        8 cm from the end effector (the opposite of :meth:`holding`)."""
        name = self._name(obj)
        closed = float(self.api.scene.gripper_state()) > 0.5
        dist = 100.0 * float(np.linalg.norm(self._centre(name) - self._ee()))
        return Condition(call_text("released", obj), not (closed and dist <= HOLD_CM),
                         f"gripper {'closed' if closed else 'open'}, the {name} {dist:.1f} cm "
                         "from it")

    # --------------------------------------------------------------- perception
    def alias(self, words: str, name: str) -> None:
        """Record that ``parse_query_obj(words)`` found ``name`` ("leftmost block" → "green
        block"), so a condition may name the object as the plan described it."""
        self._aliases[normalize_name(words)] = name

    def _name(self, obj: Any) -> str:
        text = str(getattr(obj, "name", obj))
        if is_end_effector(text):
            return "gripper"
        if (named := self._aliases.get(normalize_name(text))) is not None:
            return named  # before matching words: "block next to the purple block"
        return match_name(text, self.api.scene.object_names)

    def _ee(self) -> NDArray[np.float64]:
        return np.asarray(self.api.scene.ee_pose()[0], dtype=np.float64).reshape(3)

    def _centre(self, name: str) -> NDArray[np.float64]:
        if name == "gripper":
            return self._ee()
        return self.api.detect(name).position_world.astype(np.float64)

    def _aabb(self, name: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        if name == "gripper":
            ee = self._ee()
            return ee, ee
        lo, hi = self.api.detect(name).aabb_world
        return np.asarray(lo, float), np.asarray(hi, float)

    def _box_distance(self, points: NDArray[np.float64], name: str) -> NDArray[np.float64]:
        """Distance [m] of each point (N, 3) to ``name``'s box (0 inside), shape (N,)."""
        return box_gap(points, *self._aabb(name))


def _sliding(name: str) -> bool:
    """Whether ``name`` is a part that slides (a drawer or its handle) in the catalog."""
    try:
        return catalog.object_named(name).kind in catalog.SLIDING_KINDS
    except KeyError:
        return False


__all__ = ["AWAY_CM", "HELPERS", "Condition", "IntentChecks", "IntentResult"]
