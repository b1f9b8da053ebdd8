"""Plans completed before they run: a grasp of a free object is lifted, a drop is grasped first.

The planner's examples follow every grasp of a block with a motion ("back to default pose" or a
move elsewhere); the 1.5B model sometimes stops right after the grasp, so the fingers close on
the block and it never leaves the table — a grasp no one would call done (and the benchmark's
grasp check, which wants the block lifted, refuses). :func:`lift_after_grasp` appends the
examples' own ``composer('back to default pose')`` to such a plan; the runtime records the
addition as a ``plan_completed`` transcript event.

Only plain plans (``composer`` and ``expect`` statements) whose last sub-task grasps something
that is not part of a fixture (a handle, a drawer, a door…: lifting those would pull on them)
are completed.

A drop is several motions — the planner's examples grasp the object, lift it, carry it over the
place, open the hand — but a reworded "release the pink block over the right side of the table"
is sometimes planned as that one sub-task, which no single ``execute`` can do (the hand is not
holding the block). :func:`grasp_before_drop` replaces a sub-task that drops, releases or puts a
free object at a place, when no earlier sub-task grasped it, by the examples' own sequence
(:func:`drop_subtasks`); the sub-task's ``expect`` lines stay after the release.

"Staying on the <side> of the <object>" is the clause the model drops most (the clause checklist
asks once more, and the correction often repeats the plan): :func:`carry_stay_on` gives the
plan's one motion the instruction's clause ("move to the back side of the table while staying
on the top of the yellow block"), and drops a sub-task that went to that side of the object
instead of passing it ("move to the front side of the brown block" after the motion); a
motion that says a distance from that object the instruction never says, where the clause
belonged ("… while staying at least 10cm from the blue block" for "without leaving the top of
the blue block"), has the distance and its ``away`` post-conditions taken out first. A
distance to keep ("keep 11cm clear of the blue block") is carried the same way ("… while
staying at least 11cm from the blue block"), a sub-task that went to the object instead ("move
to a point 11cm above the blue block") dropped. A plan that takes the hand somewhere and then
sends it "back to default pose" undoes what was asked: :func:`drop_final_reset` drops that
last sub-task. "Hover 10cm over the pink block" is sometimes planned with the block as what
hovers ("hover the pink block to a point 10cm above it"), and the composer then moves the block
or the hand to 10 cm above the table: :func:`hover_over` says it as the examples do.
"""

from __future__ import annotations

import ast
import re
from typing import Final

from voxposer.lmp.checklist import HAND_MOTION
from voxposer.lmp.plan_review import expect_calls, plain_steps
from voxposer.perception.names import is_end_effector, leading_name

#: the sub-task appended after a final grasp (the planner prompt's own wording).
LIFT_SUBTASK: Final = "back to default pose"
#: how a grasping sub-task begins.
_GRASP: Final = re.compile(r"^\s*(?:grasp|grab|pick(?:\s+up)?|take|seize|hold|lift)\b", re.I)
#: a sub-task that lets an object go at a place: (object, place).
_DROP: Final = re.compile(
    r"^\s*(?:drop|release|put|place|set|lay|let go of|let)\s+(?:the\s+)?(?P<obj>[\w ]+?)"
    r"\s+(?:down\s+|go\s+|fall\s+)?(?:at|on|onto|over|above|to|into|in)\s+(?:the\s+)?"
    r"(?P<place>[\w ]+?)\s*\.?$", re.I)
#: how high above the place the object is carried before the hand opens [cm] (the examples').
CARRY_CM: Final = 9
#: "staying on the <side> of the <object>" in an instruction or a sub-task: (side, the words
#: after "of the", which begin with the object's name).
STAY_ON: Final = re.compile(
    r"\b(?:(?:stay|staying|stays|keep|keeping|remain|remaining|pass|passing|going|go)"
    r"(?:\s+(?:yourself|itself|it|the\s+(?:gripper|hand)))?\s+(?:on|over|at|along|to|by)"
    r"|(?:never|not|without|don't|do\s+not)\s+leav(?:e|es|ing))\s+"
    r"the\s+(top|bottom|(?:front|back|left|right|near|far)"
    r"(?:\s+side)?)\s+of\s+the\s+([a-z ]+)")
#: "keep 11cm clear of the blue block", "staying at least 5 cm away from the …" in an
#: instruction: (cm, object words).
_KEEP_AWAY: Final = re.compile(
    r"\b(?:keep|keeping|stay|staying|stays|remain|remaining)\s+(?:a\s+distance\s+of\s+)?"
    r"(?:at\s+least\s+)?(?P<cm>\d+(?:\.\d+)?)\s*(?:cm|centimet(?:er|re)s?)\s+(?:or\s+more\s+)?"
    r"(?:clear\s+of|away\s+from|from)\s+the\s+(?P<obj>[a-z]+(?:\s+[a-z]+)?)")
#: a sub-task that carries a distance kept from an object.
_KEEPS_AWAY: Final = re.compile(r"\b(?:at\s+least|clear\s+of|away\s+from|avoid|avoiding)\b")
#: a sub-task that takes the hand to a place.
_HAND_TO: Final = re.compile(r"^\s*(?:then\s+)?(?:move|go|head|travel)\s+(?:over\s+)?(?:to|towards?)\b")
#: words of things fixed to the scene: grasped to pull or turn them, never to lift.
_FIXED_PARTS: Final = re.compile(
    r"\b(?:handle|drawer|door|window|fridge|cabinet|knob|lever|lid|latch)s?\b", re.I)


def lift_after_grasp(code: str) -> str | None:
    """``code`` with ``composer('back to default pose')`` appended when its last sub-task
    grasps a free object (module docs); None when it needs nothing."""
    steps = plain_steps(code)
    if not steps:
        return None
    last = steps[-1][0]
    if not _GRASP.match(last) or _FIXED_PARTS.search(last):
        return None
    return f"{code.rstrip()}\ncomposer({LIFT_SUBTASK!r})"


def drop_subtasks(obj: str, place: str) -> list[str]:
    """The planner examples' sub-tasks for dropping ``obj`` at ``place``, release last."""
    return [f"grasp the {obj}", LIFT_SUBTASK, f"move the {obj} to a point {CARRY_CM}cm above the "
            f"{place}", f"release the {obj}"]


def _droppable(obj: str) -> bool:
    """Whether ``obj`` (a sub-task's words) names a free object: not a fixture's part, not the
    robot's own hand ("place the gripper at …", "put your hand at …" are motions)."""
    words = obj.removeprefix("your ").removeprefix("my ")
    return not (_FIXED_PARTS.search(obj) or is_end_effector(words))


def grasp_before_drop(code: str) -> str | None:
    """``code`` with each sub-task that drops a free object it never grasped replaced by
    :func:`drop_subtasks` (module docs); None when it needs nothing."""
    steps = plain_steps(code)
    if not steps:
        return None
    lines: list[str] = []
    grasped: list[str] = []
    changed = False
    for subtask, line, expects in steps:
        drop = _DROP.match(subtask)
        obj = drop.group("obj").strip().lower() if drop else ""
        if drop and _droppable(obj) and not any(obj in g for g in grasped):
            lines += [f"composer({s!r})" for s in drop_subtasks(obj, drop.group("place"))]
            changed = True
        else:
            lines.append(line)
        if _GRASP.match(subtask):
            grasped.append(subtask.lower())
        lines += expects
    return "\n".join(lines) if changed else None


def _clause(instruction: str, objects: tuple[str, ...] | list[str]
            ) -> tuple[str, str, re.Pattern[str], re.Pattern[str]] | None:
    """The instruction's constraint clause a plan must carry: (object, the words a sub-task
    carries it with, how a sub-task carrying it reads, how a sub-task that went to the object
    instead of keeping the constraint reads); None when it has none about a scene object."""
    text = " ".join(instruction.lower().split())

    def named(said: str) -> str | None:
        obj = leading_name(said, objects)
        return None if obj is None or obj.lower() == "table" else obj.lower()

    # the first "staying on the <side> of the <object>" about an object: "go to the back side
    # of the table" reads the same way and comes first in "go to …? stay on the … of the …"
    for stay in STAY_ON.finditer(text):
        if obj := named(stay.group(2)):
            side = stay.group(1)
            return (obj, f"while staying on the {side} of the {obj}", STAY_ON,
                    re.compile(rf"^(?:move|go)\s+to\s+(?:a\s+point\s+[\d.]+\s*cm\s+above\s+)?"
                               rf"the\s+{side}(?:\s+side)?\s+of\s+the\s+{obj}$"))
    if (away := _KEEP_AWAY.search(text)) and (obj := named(away.group("obj"))):
        cm = away.group("cm")
        return (obj, f"while staying at least {cm}cm from the {obj}", _KEEPS_AWAY,
                re.compile(rf"^(?:move|go)\s+to\s+(?:a\s+point\s+[\d.]+\s*cm\s+(?:above|away\s+"
                           rf"from|from|beside|behind|in\s+front\s+of)\s+|the\s+\w+(?:\s+side)?\s+"
                           rf"of\s+)the\s+{obj}$"))
    return None


def carry_stay_on(instruction: str, code: str, objects: tuple[str, ...] | list[str]) -> str | None:
    """``code`` with the instruction's "staying on the <side> of the <object>" (or "keep N cm
    clear of the <object>") clause given to its one motion sub-task when no sub-task carries
    it (module docs); None when it needs nothing or cannot tell which motion. ``objects``: the
    scene's object names."""
    clause = _clause(instruction, objects)
    steps = plain_steps(code)
    if clause is None or not steps:
        return None
    obj, words, carried, instead = clause
    if any(carried.search(s.lower()) and obj in s.lower() for s, _, _ in steps):
        return None
    if carried is STAY_ON:
        said = {float(n) for n in re.findall(r"\d+(?:\.\d+)?", instruction)}
        steps = [_without_unasked_distance(step, obj, said) for step in steps]
    kept = [st for st in steps if not instead.match(" ".join(st[0].lower().split()))]
    motions = [i for i, (s, _, _) in enumerate(kept)
               if HAND_MOTION.match(s) and obj not in s.lower()]
    if len(motions) != 1:
        return None
    lines: list[str] = []
    for i, (subtask, line, expects) in enumerate(kept):
        if i == motions[0]:
            line = f"composer({subtask.rstrip(' .') + ' ' + words!r})"
        lines += [line, *expects]
    return "\n".join(lines)


def _without_unasked_distance(step: tuple[str, str, list[str]], obj: str, said: set[float]
                              ) -> tuple[str, str, list[str]]:
    """``step`` (sub-task, line, expect lines) without a distance from ``obj`` the instruction
    does not say ("… while staying at least 10cm from the blue block" planned for "without
    leaving the top of the blue block": dev records, ad-hoc seed 309), nor its ``away``
    post-conditions about ``obj``; unchanged when it has none. ``said``: the numbers the
    instruction says."""
    subtask, _line, expects = step
    tail = re.search(rf"\s*,?\s+(?:while\s+|and\s+)?(?:staying|keeping|remaining|stay|keep)\s+"
                     rf"(?:at\s+least\s+)?(\d+(?:\.\d+)?)\s*(?:cm|centimet\w*)\s+(?:away\s+)?"
                     rf"from\s+the\s+{re.escape(obj)}\b", subtask, re.I)
    if tail is None or float(tail.group(1)) in said:
        return step
    words = subtask[:tail.start()] + subtask[tail.end():]
    kept: list[str] = []
    for e in expects:
        calls = expect_calls(e)
        left = [c for c in calls if not (isinstance(c.func, ast.Name) and c.func.id == "away"
                                         and obj in ast.unparse(c))]
        if len(left) == len(calls):
            kept.append(e)
        elif left:
            kept.append(f"expect({', '.join(ast.unparse(c) for c in left)})")
    return words, f"composer({words!r})", kept


#: "hover 10cm over the pink block" / "hover over it" in an instruction: (cm or None, words).
_HOVER_SAID: Final = re.compile(r"\bhover\s+(?:about\s+)?(?:(\d+(?:\.\d+)?)\s*(?:cm|centimet(?:er|re)s?)"
                                r"\s+)?(?:over|above)\s+(?:the\s+)?([a-z ]+|it)\b")
#: a sub-task that makes the object hover ("hover the pink block to a point 10cm above it").
_HOVER_THE: Final = re.compile(r"^(?:then\s+|first\s+)?hover\s+the\s+([a-z ]+)")


def _hovers(instruction: str, objects: tuple[str, ...]) -> dict[str, str | None]:
    """The objects the instruction hovers over → the height said [cm] (None: none); "it" is
    the object named last before it."""
    text = " ".join(instruction.lower().split())
    out: dict[str, str | None] = {}
    for m in _HOVER_SAID.finditer(text):
        words = m.group(2)
        if words.startswith("it"):
            before = [(text.rfind(o.lower(), 0, m.start()), o) for o in objects
                      if not is_end_effector(o) and o != "table"]
            pos, obj = max(before, default=(-1, ""))
            named = obj if pos >= 0 else None
        else:
            named = leading_name(words, objects)
        if named and named != "table":
            out.setdefault(named, m.group(1))
    return out


def hover_over(instruction: str, code: str, objects: tuple[str, ...] | list[str]) -> str | None:
    """``code`` with a sub-task that makes the object hover ("hover the pink block to a point
    10cm above it", "hover the blue block 10cm above the table") said as the hand's motion the
    instruction asks ("move to a point 10cm above the pink block", the planner examples'
    words), when the instruction hovers over that object; None when it needs nothing."""
    hovered = _hovers(instruction, tuple(objects))
    steps = plain_steps(code)
    if not hovered or not steps:
        return None
    lines: list[str] = []
    changed = False
    for subtask, line, expects in steps:
        text = " ".join(subtask.lower().split())
        m = _HOVER_THE.match(text)
        obj = leading_name(m.group(1), tuple(hovered)) if m else None
        if obj is not None:
            cm = hovered[obj]
            where = f"a point {cm}cm above" if cm else "a point above"
            line, changed = f"composer({f'move to {where} the {obj}'!r})", True
        lines += [line, *expects]
    return "\n".join(lines) if changed else None


def drop_final_reset(code: str) -> str | None:
    """``code`` without a final ``composer('back to default pose')`` that follows a motion of
    the hand to a place ("move to the right side of the table"): it would undo the motion the
    instruction asked (after a grasp, a release or a push it stays: the hand's place is not
    the point there). None when it needs nothing."""
    steps = plain_steps(code)
    if not steps or len(steps) < 2:
        return None
    last, before = steps[-1][0].lower().strip(" ."), steps[-2][0].lower()
    if last != LIFT_SUBTASK or not _HAND_TO.match(before):
        return None
    lines: list[str] = []
    for _, line, expects in steps[:-1]:
        lines += [line, *expects]
    return "\n".join([*lines, *steps[-1][2]])


__all__ = [
    "CARRY_CM",
    "LIFT_SUBTASK",
    "STAY_ON",
    "carry_stay_on",
    "drop_final_reset",
    "drop_subtasks",
    "grasp_before_drop",
    "hover_over",
    "lift_after_grasp",
]
