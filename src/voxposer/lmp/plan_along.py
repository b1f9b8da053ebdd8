"""A push along a line planned as one sub-task, said as the planner examples' two pushes.

The planner's instructions and examples push a block along a line in two sub-tasks: "push the
blue block to the near end of the green line", then "… to the far end of the green line". The
1.5B model sometimes plans the instruction as one sub-task ("slide the blue block along the
yellow line"), and the composer then reads "along the line" as a place: one target on the
line (its middle, or "a point 5cm along" it), reached after 1–3 cm of travel along it (dev
records, `benchmarks/results/dev-2026-12-06b/`: 2 of 6 dev phrasings). :func:`push_along_ends`
replaces such a sub-task by the examples' two pushes; the sub-task's ``expect`` lines follow
the second, with ``along(<object>, <line>)`` (the block went along it) when none states it.
Only plain plans (``composer`` and ``expect`` statements) whose sub-task names a scene block
and a scene line are changed; the runtime records the change as a ``plan_completed`` event.
"""

from __future__ import annotations

import re
from typing import Final

from voxposer.lmp.plan_review import plain_steps
from voxposer.perception.names import leading_name

#: a whole sub-task that pushes an object along a line: (object words, line words).
_ALONG_ONE: Final = re.compile(
    r"^(?:then\s+|and\s+|first\s+)?(?:push|slide|nudge|shove|move|drag)\s+(?:the\s+)?"
    r"(?P<obj>[a-z ]+?)\s+(?:all\s+the\s+way\s+)?(?:along|following|down)\s+(?:the\s+)?"
    r"(?P<line>[a-z ]+?line)(?:\s+by\s+pushing\s+it)?\s*\.?$")


def along_subtasks(obj: str, line: str) -> list[str]:
    """The planner examples' sub-tasks for pushing ``obj`` along ``line``."""
    return [f"push the {obj} to the near end of the {line}",
            f"push the {obj} to the far end of the {line}"]


def push_along_ends(code: str, objects: tuple[str, ...] | list[str]) -> str | None:
    """``code`` with each one-sub-task push of a block along a line replaced by
    :func:`along_subtasks` (module docs); None when it needs nothing. ``objects``: the scene's
    object names."""
    steps = plain_steps(code)
    if not steps:
        return None
    names = tuple(objects)
    lines: list[str] = []
    changed = False
    for subtask, line, expects in steps:
        m = _ALONG_ONE.match(" ".join(subtask.lower().split()))
        obj = leading_name(m.group("obj"), names) if m else None
        on = leading_name(m.group("line"), names) if m else None
        if m is None or obj is None or on is None or not on.lower().endswith("line") \
                or obj.lower().endswith("line"):
            lines += [line, *expects]
            continue
        lines += [f"composer({s!r})" for s in along_subtasks(obj, on)]
        if not any("along(" in e for e in expects):
            expects = [*expects, f"expect(along({obj!r}, {on!r}))"]
        lines += expects
        changed = True
    return "\n".join(lines) if changed else None


__all__ = ["along_subtasks", "push_along_ends"]
