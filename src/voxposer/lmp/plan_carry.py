"""A constraint the planner states only in a post-condition, carried into its sub-task's words.

The planner writes what must hold after each sub-task (``expect(...)``) and the sub-task's words
(``composer('...')``) that the composer turns into value maps. The 1.5B model sometimes keeps a
clause of the instruction only in the post-condition: "push the yellow block to the front right
corner of the table; stay away from the green block" planned as ``composer('push the yellow
block to the front right corner of the table')`` with ``expect(away('yellow block', 'green
block'))`` (dev records, ``benchmarks/results/dev-2026-12-06/``: 3 of 6 staying-away pushes).
The composer never reads the post-condition, so no avoidance map is built and the path goes
where it likes; the run then fails its own condition. The plan's own condition says what the
words lack, in whatever words the instruction used, so :func:`carry_stated_constraints` gives
the sub-task the words the composer's examples read:

- ``away('gripper', <object>, cm=<n>)`` under a motion of the hand whose words keep no distance
  from that object: "… while staying at least <n>cm from the <object>" (without ``cm``, "…
  while staying away from the <object>");
- ``speed('gripper', <factor>, near=<object>, cm=<n>)`` or ``speed(…, inside=<part>)`` under a
  motion whose words say no speed: "… at <the instruction's speed phrase> when within <n>cm of
  the <object>" (or "… in the <part> of the table"); a ``speed`` without a zone takes the
  instruction's zone when it says one, else applies to the whole motion. The phrase is the
  instruction's own when it says one of the same direction with a speed noun ("at a quarter
  of the speed"), else the examples' words for the factor ("faster speed" for 2) or
  "<factor>x speed".

For a push ("push/slide/nudge the <block> …"), an ``away`` of the pushed block or the gripper
is carried the same way ("… while staying away from the <object>": the examples' words for a
push that avoids). Only plain plans (``composer`` and ``expect`` statements) are changed, and
only motions of the hand ("move/go/head/travel/get to …") and pushes, not grasps. The runtime
records each change as a ``plan_completed`` transcript event.
"""

from __future__ import annotations

import ast
import re
from typing import Final

from voxposer.lmp.checklist import (
    HAND_MOTION_START,
    NEAR_SAID,
    PUSH_SUBTASK,
    REGION_SAID,
    says_speed,
)
from voxposer.lmp.plan_review import expect_calls, plain_steps
from voxposer.lmp.speed_words import speed_factor, speed_span
from voxposer.perception.names import is_end_effector, leading_name

#: a sub-task that moves the hand to a place (not a grasp, push or release).
_HAND_MOTION: Final = re.compile(
    HAND_MOTION_START + r"(?!.*\b(?:push|grasp|pick|drop|release)\b)", re.I)

#: the speed words of the planner's examples for the factors they use.
_NAMED_SCALES: Final = {2.0: "faster speed", 0.5: "half of the speed",
                        0.25: "a quarter of the speed"}


def _string(node: ast.expr | None) -> str | None:
    return node.value if isinstance(node, ast.Constant) and isinstance(node.value, str) else None


def _number(node: ast.expr | None) -> float | None:
    if isinstance(node, ast.Constant) and isinstance(node.value, int | float) \
            and not isinstance(node.value, bool):
        return float(node.value)
    return None


def _keyword(call: ast.Call, name: str, position: int | None = None) -> ast.expr | None:
    for k in call.keywords:
        if k.arg == name:
            return k.value
    return call.args[position] if position is not None and len(call.args) > position else None


def _away_words(call: ast.Call, subtask: str, objects: tuple[str, ...],
                pushed: str | None) -> str | None:
    """The words an ``away(<what moves>, <object>[, cm])`` condition asks of ``subtask`` (what
    moves: the gripper, or the ``pushed`` object of a push); None
    when the sub-task already names that object (it keeps the distance in its own words, or
    goes there: nothing to add), or the call is not of that shape."""
    what, other = _string(_keyword(call, "obj", 0)), _string(_keyword(call, "target", 1))
    if what is None or other is None or not (is_end_effector(what) or (
            pushed is not None and leading_name(what.lower(), objects) == pushed)):
        return None
    obj = leading_name(other.lower(), objects)
    text = subtask.lower()
    if obj is None or obj.lower() == "table" or obj.lower() in text:
        return None
    cm = _number(_keyword(call, "cm", 2))
    return (f"while staying at least {cm:g}cm from the {obj}" if cm is not None and pushed is None
            else f"while staying away from the {obj}")


def _speed_words(call: ast.Call, subtask: str, instruction: str,
                 objects: tuple[str, ...]) -> str | None:
    """The words a ``speed('gripper', <factor>[, near=…|inside=…])`` condition asks of
    ``subtask``; None when the sub-task already says a speed or the call is not of that
    shape. An unscoped one takes the instruction's zone ("within 5cm of the <object>", "in
    the right side of the table"), when it says one."""
    what, scale = _string(_keyword(call, "obj", 0)), _number(_keyword(call, "scale", 1))
    if what is None or scale is None or scale <= 0 or not is_end_effector(what) \
            or says_speed(subtask):
        return None
    near, inside = _string(_keyword(call, "near")), _string(_keyword(call, "inside"))
    inside = inside or _string(_keyword(call, "side"))
    cm = _number(_keyword(call, "cm"))
    said_text = " ".join(instruction.lower().split())
    if near is None and inside is None:  # unscoped: the instruction's own zone, if it says one
        if (zone := NEAR_SAID.search(said_text)) is not None:
            near, cm = zone.group(2), float(zone.group(1))
        elif (part := REGION_SAID.search(said_text)) is not None:
            inside = part.group(1)
    span = speed_span(said_text)
    said = said_text[span[0]:span[1]].strip() if span else ""
    factor = speed_factor(said) if re.search(r"\b(?:speed|pace|velocity)\b", said) else None
    phrase = (said if factor is not None and (factor > 1) == (scale > 1)
              else _NAMED_SCALES.get(scale, f"{scale:g}x speed"))
    phrase = phrase if phrase.startswith("at ") else f"at {phrase}"
    if near is not None:
        obj = leading_name(near.lower(), objects)
        if obj is None:
            return None
        return f"{phrase} when within {cm:g}cm of the {obj}" if cm else f"{phrase} near the {obj}"
    if inside is not None:
        return f"{phrase} in the {inside} of the table"
    return phrase


def carry_stated_constraints(instruction: str, code: str, objects: tuple[str, ...] | list[str]
                             ) -> tuple[str, list[str]] | None:
    """``code`` with each hand motion or push given the words of the constraints its
    post-conditions state and its words lack (module docs), and the sub-tasks so changed; None
    when the plan needs nothing. ``objects``: the scene's object names."""
    steps = plain_steps(code)
    if not steps:
        return None
    names = tuple(objects)
    lines: list[str] = []
    changed: list[str] = []
    for subtask, line, expects in steps:
        push = PUSH_SUBTASK.match(subtask)
        pushed = leading_name(push.group("words").lower(), names) if push else None
        if _HAND_MOTION.match(subtask) or pushed is not None:
            added: list[str] = []
            for cond in (c for e in expects for c in expect_calls(e)):
                helper = cond.func.id  # type: ignore[attr-defined]
                words = (_away_words(cond, subtask, names, pushed) if helper == "away" else
                         _speed_words(cond, subtask, instruction, names)
                         if helper == "speed" and pushed is None else None)
                if words and words not in added:
                    added.append(words)
            if added:
                new = " ".join([subtask.rstrip(" ."), *added])
                line = f"composer({new!r})"
                changed.append(new)
        lines += [line, *expects]
    return ("\n".join(lines), changed) if changed else None


__all__ = ["carry_stated_constraints"]
