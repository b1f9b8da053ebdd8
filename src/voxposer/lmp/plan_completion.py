"""Plans completed before they run: a plan that ends on a grasp of a free object lifts it.

The planner's examples follow every grasp of a block with a motion ("back to default pose" or a
move elsewhere); the 1.5B model sometimes stops right after the grasp, so the fingers close on
the block and it never leaves the table — a grasp no one would call done (and the benchmark's
grasp check, which wants the block lifted, refuses). :func:`lift_after_grasp` appends the
examples' own ``composer('back to default pose')`` to such a plan; the runtime records the
addition as a ``plan_completed`` transcript event.

Only plain plans (``composer`` and ``expect`` statements) whose last sub-task grasps something
that is not part of a fixture (a handle, a drawer, a door…: lifting those would pull on them)
are completed.
"""

from __future__ import annotations

import re
from typing import Final

from voxposer.lmp.plan_review import plain_steps

#: the sub-task appended after a final grasp (the planner prompt's own wording).
LIFT_SUBTASK: Final = "back to default pose"
#: how a grasping sub-task begins.
_GRASP: Final = re.compile(r"^\s*(?:grasp|grab|pick(?:\s+up)?|take|seize|hold|lift)\b", re.I)
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


__all__ = ["LIFT_SUBTASK", "lift_after_grasp"]
