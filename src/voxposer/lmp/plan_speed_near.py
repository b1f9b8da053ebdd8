"""A speed near an object planned as a sub-task of its own, folded into the motion it constrains.

"reach the back left corner of the table; when the pink block is less than 5cm away, move at
faster speed" was planned (dev records, an extra dev phrasing, ad-hoc seed 305) as
``composer('move to the back left corner of the table')`` then ``composer('speed(gripper, 2,
away="pink block", cm=5)')``: the speed clause became a sub-task with no motion of its own, here
even written as a helper call. The hand reached the corner at the default speed everywhere, and
the second sub-task had nowhere to go. :func:`speed_near_folded` mends it without asking: when
the instruction says a speed, one distance in cm and one scene object, and the plan has one
motion of the hand that says no speed beside sub-tasks that say a speed and are no motion (a
constraint alone, or code), those sub-tasks are dropped and the motion says the speed near the
object as the composer's examples do ("… while moving at faster speed when within 5cm from the
pink block"). Only plain plans (``composer`` and ``expect`` statements); the dropped sub-tasks'
post-conditions go with them (they measured a sub-task that no longer exists).
"""

from __future__ import annotations

import re
from typing import Final

from voxposer.lmp.checklist import HAND_MOTION, constraint_only, says_speed
from voxposer.lmp.plan_review import plain_steps
from voxposer.lmp.speed_words import speed_factor, speed_span
from voxposer.perception.names import is_end_effector

#: a sub-task written as code, not words ("speed(gripper, 2, away='pink block', cm=5)").
_CALL: Final = re.compile(r"^\s*[a-z_]+\s*\(", re.I)
#: a distance in centimetres: (number).
_CM: Final = re.compile(r"(?<![\w.])(\d+(?:\.\d+)?)\s*(?:cm\b|centimet)")


def speed_near_folded(instruction: str, code: str, names: tuple[str, ...] = ()) -> str | None:
    """``code`` with a speed-only sub-task folded into the hand's one motion (module docs);
    None when there is nothing to mend. ``names``: the scene's object names."""
    said = " ".join(instruction.lower().split())
    steps = plain_steps(code)
    span = speed_span(said)
    if steps is None or speed_factor(said) is None or span is None:
        return None
    distances = set(_CM.findall(said))
    objects = [n for n in names
               if not is_end_effector(n) and n != "table"
               and re.search(rf"\b{re.escape(n)}\b", said)]
    if len(distances) != 1 or len(objects) != 1:
        return None
    motions = [i for i, (s, _, _) in enumerate(steps)
               if HAND_MOTION.match(s) and not constraint_only(s)]
    alone = [i for i, (s, _, _) in enumerate(steps)
             if i not in motions and says_speed(s) and (constraint_only(s) or _CALL.match(s))]
    if len(motions) != 1 or says_speed(steps[motions[0]][0]) or not alone \
            or len(motions) + len(alone) != len(steps):
        return None
    phrase = said[span[0]:span[1]].strip().removeprefix("at ")
    cm = distances.pop()
    lines: list[str] = []
    for i, (subtask, _line, expects) in enumerate(steps):
        if i in alone:
            continue
        words = f"{subtask.rstrip(' .')} while moving at {phrase} when within {cm}cm from the " \
                f"{objects[0]}"
        lines += [f"composer({words!r})", *expects]
    return "\n".join(lines)


__all__ = ["speed_near_folded"]
