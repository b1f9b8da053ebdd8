"""Post-conditions derived from a plan's own words, and the instruction's speed kept.

The planner states after each sub-task what must then hold (``expect(...)``,
:mod:`voxposer.lmp.intent`), and the post-condition checklist
(:mod:`voxposer.lmp.intent_checklist`) asks it once more when a constraint of a sub-task goes
unmeasured. The 1.5B model often answers the same plan again, so a run would claim a success
its own sub-tasks' words deny. :func:`derive_conditions` then completes the conditions from
those words, as the checklist asks:

- "move to the <side> of the <object>": ``on('gripper', <object>, <side>)`` (beside it on
  that side; ``above`` for its top), unless an ``on``/``above`` of that object is stated;
  "hover / move to a point <n>cm above the <object>": ``above('gripper', <object>, cm=<n>)``;
- "move away from the <object>": ``far('gripper', <object>)`` (where it ends); an ``away``
  naming that object is dropped — the path starts beside it;
- "move to the <place> of the table": an ``on(<object>, 'table', <place>)`` is said of the
  gripper (the hand goes there); "<n>cm above the <object>": an ``above(<object>, 'table')``
  is dropped (the object does not hover);
- a condition an earlier sub-task already states is dropped from a later one, and one on the
  hand beside an object only an earlier sub-task names is moved to it (a plan that states
  every condition after its last sub-task);
- "staying on the <side> of the <object>": ``passed_on('gripper', <object>, <side>)`` (the side
  kept while passing); an ``on(...)`` beside that object, or of that object on the table, is
  dropped — the hand only passes it, and the object does not move;
- "push the <object> along the <line>": ``along(<object>, <line>)`` (it went along it, not
  only onto it);
- "push the <object> …": ``moved(<object>)`` (a push that never moved the block did nothing,
  whatever ``on`` says of where the block already was); an avoidance clause measured on the
  gripper is measured on the pushed object;
- "release/drop the <object>": ``released(<object>)``;
- a speed clause: ``speed(<what moves>, <factor>)`` with the factor its words ask
  (:mod:`voxposer.lmp.speed_words`), restricted ``near=`` the object or ``inside=`` the table
  part the sub-task names; a stated factor of the wrong direction is set to the words';
- an avoidance clause ("staying away from the <object>", "at least 5cm from …"):
  ``away(<what moves>, <object>[, cm=<n>])``.

:func:`keep_instruction_speed` fixes the plan itself: a sub-task whose speed asks the opposite
of the instruction's ("at faster speed" planned for "at a quarter of the speed") gets the
instruction's speed phrase instead. Only plain plans (``composer`` and ``expect`` statements)
are changed; the runtime records each change as a ``plan_completed`` transcript event.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable
from typing import Final, NamedTuple

from voxposer.lmp.checklist import AVOID_WORDS, MOVE_AWAY, NEAR_SAID, PUSH_SUBTASK, REGION_SAID
from voxposer.lmp.plan_completion import STAY_ON
from voxposer.lmp.plan_review import expect_calls, plain_steps
from voxposer.lmp.speed_words import same_direction, speed_factor, speed_span
from voxposer.perception.names import is_end_effector, leading_name

_BESIDE: Final = re.compile(r"^(?:then\s+)?(?:move|go|head)\s+to\s+the\s+(top|(?:front|back|left|right)"
                            r"(?:\s+side)?)\s+of\s+the\s+([a-z ]+?)\.?$")
_ABOVE: Final = re.compile(r"^(?:then\s+|first\s+)?(?:move|go|head|hover)\b.*?\b(\d+(?:\.\d+)?)\s*"
                           r"(?:cm|centimet(?:er|re)s?)\s+(?:above|over)\s+(?:the\s+)?([a-z ]+)")
_HOVER_OBJ: Final = re.compile(r"^(?:then\s+|first\s+)?hover\s+(?:over\s+|above\s+)?(?:the\s+)?"
                               r"([a-z ]+)")
_TO_PLACE: Final = re.compile(r"^(?:then\s+|and\s+)?(?:move|go|head)\s+to\s+the\s+((?:[a-z]+\s+){0,2}"
                              r"(?:side|corner))\s+of\s+the\s+table\.?$")
_ALONG: Final = re.compile(r"\b(?:along|following|down|up)\s+the\s+([a-z]+\s+line)\b")
_RELEASE: Final = re.compile(r"^(?:then\s+|and\s+)?(?:release|drop|let\s+go\s+of|put\s+down)\s+"
                             r"(?:the\s+)?([a-z ]+)")
_AWAY: Final = re.compile(r"\b(?:away\s+from|avoid|avoiding|clear\s+of|around|from)\s+the\s+"
                          r"([a-z ]+)")
_AT_LEAST: Final = re.compile(r"\bat\s+least\s+(\d+(?:\.\d+)?)\s*(?:cm|centimet(?:er|re)s?)")


class Stated(NamedTuple):
    """A condition inside an ``expect(...)``: its helper, string arguments (lower case, ""
    when not a string constant), keyword names, and source text."""

    helper: str
    args: tuple[str, ...]
    keywords: frozenset[str]
    source: str


def _stated(line: str) -> list[Stated]:
    """The conditions of one ``expect(...)`` line (none when it does not parse)."""
    return [Stated(call.func.id,  # type: ignore[attr-defined]
                   tuple(a.value.lower() if isinstance(a, ast.Constant) and isinstance(a.value, str)
                         else "" for a in call.args),
                   frozenset(k.arg for k in call.keywords if k.arg),
                   ast.get_source_segment(line, call) or "") for call in expect_calls(line)]


def _object(words: str, objects: tuple[str, ...]) -> str | None:
    """The scene object ``words`` begin with (the longest name), None when none does."""
    return leading_name(words, objects)


def _mover(text: str, objects: tuple[str, ...]) -> str:
    """What a sub-task moves: the pushed object, else the gripper."""
    push = PUSH_SUBTASK.match(text)
    return (_object(push.group("words").lower(), objects) or "gripper") if push else "gripper"


def _stated_scale(cond: Stated) -> float | None:
    try:
        call = ast.parse(cond.source).body[0].value  # type: ignore[attr-defined]
        value = call.args[1].value
    except (SyntaxError, IndexError, AttributeError):
        return None
    return float(value) if isinstance(value, int | float) else None


def _speed(text: str, conds: list[Stated], objects: tuple[str, ...]
           ) -> tuple[list[Stated], list[str]]:
    """``conds`` with the speed ``text`` asks measured (module docs), and the changes."""
    factor = speed_factor(text)
    if factor is None:
        return conds, []
    near, region = NEAR_SAID.search(text), REGION_SAID.search(text)
    near_obj = _object(near.group(2), objects) if near else None
    where = (f", near={near_obj!r}, cm={float(near.group(1)):g}" if near and near_obj
             else f", inside={region.group(1)!r}" if region else "")
    speeds = [c for c in conds if c.helper == "speed"]
    keep = [c for c in conds if c.helper != "speed"]
    notes: list[str] = []
    for c in speeds:
        scale = _stated_scale(c)
        scoped = c.keywords & {"near", "inside", "side"} or not where
        if scale is not None and same_direction(scale, factor) and scoped:
            keep.append(c)
            continue
        subject = c.args[0] if c.args and c.args[0] else "gripper"
        new = f"speed({subject!r}, {factor:g}{where})"
        keep.append(Stated("speed", (subject,), frozenset(), new))
        notes.append(f"{c.source} → {new}")
    if not speeds:  # the end effector's speed, whatever it moves
        new = f"speed('gripper', {factor:g}{where})"
        keep.append(Stated("speed", ("gripper",), frozenset(), new))
        notes.append(f"+ {new}")
    return keep, notes


def _hand_place(text: str, conds: list[Stated], objects: tuple[str, ...],
                add: Callable[[str, tuple[str, ...], str], None], notes: list[str]) -> None:
    """Where a hand motion ends, from ``text``: ``above`` for "<n>cm above the <object>"
    ("it": the object the sub-task names first), ``far`` for "move away from the <object>"
    (``conds`` changed in place)."""
    if (high := _ABOVE.match(text)):
        named = _object(high.group(2), objects)
        if named is None and high.group(2).startswith("it") and (hover := _HOVER_OBJ.match(text)):
            named = _object(hover.group(1), objects)
        for c in [c for c in conds if named and c.helper == "above"
                  and c.args[:2] == (named.lower(), "table")]:  # the object does not hover
            conds.remove(c)
            notes.append(f"- {c.source}")
        if named and named != "table" and not any(
                c.helper in ("on", "above") and c.args[1:2] == (named.lower(),) for c in conds):
            add("above", ("gripper", named.lower()),
                f"above('gripper', {named!r}, cm={float(high.group(1)):g})")
    if (place := _TO_PLACE.match(text)):  # the hand goes there, not an object stated
        for c in [c for c in conds if c.helper == "on" and c.args[1:3] == ("table", place.group(1))
                  and c.args[0] and not is_end_effector(c.args[0])]:
            new = f"on('gripper', 'table', {place.group(1)!r})"
            conds[conds.index(c)] = c._replace(args=("gripper", *c.args[1:]), source=new)
            notes.append(f"{c.source} → {new}")
    if (leave := MOVE_AWAY.match(text)) and (named := _object(leave.group("obj"), objects)):
        low = named.lower()
        dropped = [c for c in conds if c.helper == "away" and low in c.args]
        for c in dropped:
            conds.remove(c)
            notes.append(f"- {c.source}")
        if not any(c.helper == "far" for c in conds):
            add("far", ("gripper", low), f"far('gripper', {named!r})")


def derive_subtask(subtask: str, conds: list[Stated], objects: tuple[str, ...]
                   ) -> tuple[list[Stated], list[str]]:
    """``conds`` completed from ``subtask``'s words (module docs), with the changes in words."""
    text = " ".join(subtask.lower().split())
    mover = _mover(text, objects)
    notes: list[str] = []

    def add(helper: str, args: tuple[str, ...], source: str) -> None:
        conds.append(Stated(helper, args, frozenset(), source))
        notes.append(f"+ {source}")

    if (stay := STAY_ON.search(text)) and (obj := _object(stay.group(2), objects)) \
            and obj != "table":
        low = obj.lower()
        dropped = [c for c in conds if c.helper == "on" and low in c.args[:2]]
        conds = [c for c in conds if c not in dropped]
        notes += [f"- {c.source}" for c in dropped]
        if not any(c.helper == "passed_on" and c.args[1:2] == (low,) for c in conds):
            add("passed_on", (mover, low), f"passed_on({mover!r}, {obj!r}, {stay.group(1)!r})")
    if (beside := _BESIDE.match(text)) and (obj := _object(beside.group(2), objects)) \
            and obj != "table" and not any(c.helper in ("on", "above") and c.args[1:2]
                                          == (obj.lower(),) for c in conds):
        side = beside.group(1)
        if side == "top":
            add("above", ("gripper", obj.lower()), f"above('gripper', {obj!r})")
        else:
            side = side if side.endswith("side") else f"{side} side"
            add("on", ("gripper", obj.lower()), f"on('gripper', {obj!r}, {side!r})")
    _hand_place(text, conds, objects, add, notes)
    if mover != "gripper":
        if not any(c.helper == "moved" and c.args[:1] == (mover.lower(),) for c in conds):
            add("moved", (mover.lower(),), f"moved({mover!r})")
        line = _ALONG.search(text)
        if line and (name := _object(line.group(1), objects)) \
                and not any(c.helper == "along" for c in conds):
            add("along", (mover.lower(), name.lower()), f"along({mover!r}, {name!r})")
        for c in [c for c in conds if c.helper == "away" and is_end_effector(c.args[0])]:
            new = c.source.replace(repr(c.args[0]), repr(mover), 1)
            if new != c.source:
                conds[conds.index(c)] = c._replace(args=(mover.lower(), *c.args[1:]), source=new)
                notes.append(f"{c.source} → {new}")
    if (rel := _RELEASE.match(text)) and (obj := _object(rel.group(1), objects)) \
            and not is_end_effector(obj) \
            and not any(c.helper in ("released", "holding") for c in conds):
        add("released", (obj.lower(),), f"released({obj!r})")
    conds, speed_notes = _speed(text, conds, objects)
    notes += speed_notes
    avoids = set(re.findall(r"[a-z]+", text)) & AVOID_WORDS or _AT_LEAST.search(text)
    if avoids and not STAY_ON.search(text) and not MOVE_AWAY.match(text) \
            and not any(c.helper == "away" for c in conds):
        for m in _AWAY.finditer(text):
            if (obj := _object(m.group(1), objects)) and obj.lower() != mover.lower():
                least = _AT_LEAST.search(text)
                cm = f", cm={float(least.group(1)):g}" if least else ""
                add("away", (mover.lower(), obj.lower()), f"away({mover!r}, {obj!r}{cm})")
                break
    return conds, notes


def derive_conditions(code: str, objects: tuple[str, ...] | list[str]
                      ) -> tuple[str, list[str]] | None:
    """``code`` with each sub-task's ``expect`` completed from its words (module docs), and
    the changes in words; None when the plan is not plain or needs nothing. ``objects``: the
    scene's object names."""
    steps = plain_steps(code)
    if not steps:
        return None
    names = tuple(objects)
    stated, notes, moved = _relocated(steps)
    lines: list[str] = []
    earlier: set[str] = set()
    for k, ((subtask, line, expects), conds) in enumerate(zip(steps, stated, strict=True)):
        done, changed = derive_subtask(subtask, list(conds), names)
        own = {c.source for c in derive_subtask(subtask, [], names)[0]}  # its words ask these
        again = [c for c in done if c.source in earlier and c.source not in own]  # stated late
        if again:
            done = [c for c in done if c not in again]
            changed = [*changed, *(f"- {c.source} (stated for an earlier sub-task)" for c in again)]
        earlier |= {c.source for c in done}
        lines.append(line)
        if changed or k in moved:
            notes += [f"{subtask!r}: {n}" for n in changed]
            if done:
                lines.append(f"expect({', '.join(c.source for c in done)})")
        else:
            lines += expects
    return ("\n".join(lines), notes) if notes else None


def _relocated(steps: list[tuple[str, str, list[str]]]
               ) -> tuple[list[list[Stated]], list[str], set[int]]:
    """The conditions stated after each step, where a condition on the hand beside an object
    (``near``/``on``/``above``) that its sub-task does not name but an earlier one does is
    moved to the latest such sub-task (a plan that states them late); with the moves in words
    and the steps whose conditions changed."""
    stated = [[c for e in expects for c in _stated(e)] for _, _, expects in steps]
    texts = [" ".join(s.lower().split()) for s, _, _ in steps]
    notes: list[str] = []
    moved: set[int] = set()
    for k in range(1, len(steps)):
        for c in list(stated[k]):
            other = c.args[1] if len(c.args) > 1 else ""
            if c.helper not in ("near", "on", "above") or not c.args[0] \
                    or not is_end_effector(c.args[0]) or other in ("", "table") \
                    or other in texts[k]:
                continue
            j = next((j for j in range(k - 1, -1, -1) if other in texts[j]), None)
            if j is not None:
                stated[k].remove(c)
                stated[j].append(c)
                moved |= {j, k}
                notes.append(f"{steps[k][0]!r}: {c.source} moved to {steps[j][0]!r}")
    return stated, notes, moved


def keep_instruction_speed(instruction: str, code: str) -> tuple[str, list[str]] | None:
    """``code`` with each sub-task whose speed asks the opposite of ``instruction``'s given
    the instruction's speed phrase; None when nothing needs it or the plan is not plain."""
    asked, said = speed_factor(instruction), speed_span(instruction)
    steps = plain_steps(code)
    if asked is None or said is None or not steps:
        return None
    phrase = instruction[said[0]:said[1]]
    lines: list[str] = []
    notes: list[str] = []
    for subtask, line, expects in steps:
        factor, span = speed_factor(subtask), speed_span(subtask)
        if factor is not None and span is not None and not same_direction(factor, asked):
            fixed = subtask[:span[0]] + phrase + subtask[span[1]:]
            line = f"composer({fixed!r})"
            notes.append(f"{subtask!r} → {fixed!r}")
        lines += [line, *expects]
    return ("\n".join(lines), notes) if notes else None


__all__ = ["Stated", "derive_conditions", "derive_subtask", "keep_instruction_speed"]
