"""A motion to the object the instruction only asks to keep away from, mended into an avoidance.

"push the yellow block to the right side of the table and go around the pink block" was planned
(dev records of reworded staying-away pushes) as ``composer('push the yellow block to the right
side of the table')`` then ``composer('move around the pink block')``: the push, built with no
avoidance map, went where it liked, and the hand then visited the block to be avoided. Asked to
fix it, the model answered with that sub-task alone. :func:`fold_avoided` drops such sub-tasks
(:func:`voxposer.lmp.unasked.to_avoided`, with their post-conditions) and, when no sub-task left
names the object — dropped so, or never named ("move the yellow block to the front right
corner of the table with pushes" for "…, steering it around the pink block", kept when the
clause checklist asked) — says "while staying away from the <object>" in the plan's pushes —
or, in a plan without pushes, its motions of the hand to a place — the words the composer's
examples read for a motion that avoids. Only plain plans (``composer`` and ``expect``
statements).
"""

from __future__ import annotations

import re
from typing import Final

from voxposer.lmp.checklist import HAND_MOTION_START, PUSH_SUBTASK
from voxposer.lmp.plan_review import plain_steps
from voxposer.lmp.unasked import avoided_objects, to_avoided

#: a sub-task that moves the hand to somewhere (not the default pose, a grasp or a release).
_TO_PLACE: Final = re.compile(
    HAND_MOTION_START + r"(?!.*\b(?:default|grasp|release|drop)\b).*\b(?:to|above|over)\b", re.I)


def _with_avoidance(subtask: str, avoided: str) -> str:
    return f"{subtask.rstrip(' .')} while staying away from the {avoided}"


def fold_avoided(instruction: str, code: str, names: tuple[str, ...] = ()) -> str | None:
    """``code`` without its motions to what ``instruction`` only asks to avoid, the avoidance
    said in its pushes or motions instead; None when there is nothing to mend."""
    del names  # the object names are not needed: the instruction names what to avoid
    steps = plain_steps(code)
    avoided = sorted(avoided_objects(instruction))
    if steps is None or not avoided:
        return None
    kept = [s for s in steps if not any(to_avoided(s[0], a) for a in avoided)]
    unnamed = [a for a in avoided if not any(a in s.lower() for s, _, _ in kept)]
    if not kept or (len(kept) == len(steps) and not unnamed):
        return None
    lines: list[str] = []
    pushes = {i for i, s in enumerate(kept) if PUSH_SUBTASK.match(s[0])}
    movers = pushes or {i for i, s in enumerate(kept) if _TO_PLACE.match(s[0])}
    for i, (subtask, _, expects) in enumerate(kept):
        if i in movers:
            for name in unnamed:
                subtask = _with_avoidance(subtask, name)
        lines += [f"composer({subtask!r})", *expects]
    return "\n".join(lines)


__all__ = ["fold_avoided"]
