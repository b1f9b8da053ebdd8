"""The post-condition checklist: every constraint of a sub-task needs a post-condition that
measures it.

The planner states after each ``composer(...)`` call what must then hold (``expect(...)``,
:mod:`voxposer.lmp.intent`). A small model often writes the end state only — "staying on the
top of the blue block" stated as ``on('gripper', 'table', 'top')``, a speed in a table part
without ``inside=``, a push's distance to the obstacle measured on the gripper instead of the
pushed block — or no post-condition at all; the run then claims a success the task's check
denies. Before the plan runs, :func:`intent_gaps` reads each sub-task's words and the
conditions stated after it and names what is missing:

- a speed clause without a ``speed`` condition, or with one that leaves out the object it is
  near (``near=``) or the table part it holds in (``inside=``) when the sub-task names them;
- an avoidance clause without an ``away`` condition; in a push, ``away`` on the gripper
  instead of the pushed object;
- "staying on the <side> of <object>" without ``passed_on`` (the side kept while passing);
- a push whose conditions say nothing about the pushed object (``moved``, ``on``, ``near``).

A plan that states no post-condition at all is left alone (the run then claims success when
no sub-task fails). Lexical like the clause checklist (:mod:`voxposer.lmp.checklist`), and like it it can only
ask the planner once more; the plan with fewer gaps runs.
"""

from __future__ import annotations

import ast
import re
from typing import Final, NamedTuple

from voxposer.lmp.checklist import (
    AVOID_WORDS,
    MOVE_AWAY,
    PUSH_SUBTASK,
    REGION_SAID,
    SPEED_WORDS,
    ClauseGap,
)
from voxposer.perception.names import is_end_effector, normalize_name

#: the post-condition helpers the checklist reads (:data:`voxposer.lmp.intent.HELPERS`).
_CONDITIONS: Final = frozenset({"moved", "near", "on", "above", "away", "far", "passed_on",
                                "speed", "holding", "released", "along"})
_NEAR: Final = re.compile(r"\b(?:within|near|close to|closer than|next to|around)\b[^,;]*?"
                          r"\bthe\s+(?:[a-z]+\s+)?(?:block|cube|object|line|drawer|handle|box)\b")
_STAY_ON: Final = re.compile(r"\b(?:stay|staying|stays|keep|keeping|remain|remaining|pass|"
                             r"passing)\s+(?:on|over|at|along)\s+the\s+(?:top|[a-z]+\s+side)\s+"
                             r"of\s+the\b(?!\s+table\b)")
_NO_MOTION: Final = re.compile(r"^(?:back to (?:the )?default pose|release|open the gripper|"
                               r"close the gripper|let go)\b")


class Condition(NamedTuple):
    """One condition inside an ``expect(...)``: the helper, its first argument (the object
    it is about, lower case, "" when not a string), its second (what it is measured against,
    "" likewise) and its keyword names."""

    helper: str
    subject: str
    other: str
    keywords: frozenset[str]


def subtask_conditions(code: str) -> list[tuple[str, list[Condition]]] | None:
    """Each ``composer('<sub-task>')`` of ``code`` in source order with the conditions of the
    ``expect`` calls after it (before the next sub-task); None when the code does not parse."""
    try:
        tree = ast.parse(code)
    except SyntaxError:
        return None
    calls = sorted((n for n in ast.walk(tree) if isinstance(n, ast.Call)
                    and isinstance(n.func, ast.Name) and n.func.id in ("composer", "expect")),
                   key=lambda n: (n.lineno, n.col_offset))
    out: list[tuple[str, list[Condition]]] = []
    for call in calls:
        if call.func.id == "composer":  # type: ignore[attr-defined]
            arg = call.args[0] if call.args else None
            text = arg.value if isinstance(arg, ast.Constant) and isinstance(arg.value, str) \
                else ""
            out.append((text, []))
        elif out:
            out[-1][1].extend(_conditions(call))
    return out


def _conditions(expect: ast.Call) -> list[Condition]:
    found = []
    for arg in expect.args:
        if (isinstance(arg, ast.Call) and isinstance(arg.func, ast.Name)
                and arg.func.id in _CONDITIONS):
            first, second = (_text(arg.args[i]) if len(arg.args) > i else "" for i in (0, 1))
            found.append(Condition(arg.func.id, first, second,
                                   frozenset(k.arg for k in arg.keywords if k.arg)))
    return found


def _text(node: ast.expr) -> str:
    return node.value.lower() if isinstance(node, ast.Constant) and isinstance(node.value, str) \
        else ""


def _words(text: str) -> set[str]:
    return set(re.findall(r"[a-z]+", normalize_name(text)))


def subtask_gaps(subtask: str, conditions: list[Condition],
                 later: tuple[Condition, ...] = ()) -> list[str]:
    """What the conditions stated after ``subtask`` leave unmeasured, in words (empty: none);
    where a push ends may also be stated after a later sub-task (``later``: their conditions;
    a push to a line's near end, then to its far end)."""
    text = " ".join(subtask.lower().split())
    words = _words(text)
    by: dict[str, list[Condition]] = {}
    for cond in conditions:
        by.setdefault(cond.helper, []).append(cond)
    gaps: list[str] = []
    push = PUSH_SUBTASK.match(text)
    pushed = next(iter(push.group("words").lower().split()), None) if push else None
    if words & SPEED_WORDS:
        speeds = by.get("speed", [])
        if not speeds:
            gaps.append("its speed: speed('gripper', <scale>) measures it")
        elif _NEAR.search(text) and not any("near" in s.keywords for s in speeds):
            gaps.append("where its speed holds: speed('gripper', <scale>, near='<object>', "
                        "cm=<distance>) measures it only near that object")
        elif REGION_SAID.search(text) and not any(s.keywords & {"inside", "side"} for s in speeds):
            gaps.append("where its speed holds: speed('gripper', <scale>, inside='<table part>') "
                        "measures it only over that part of the table")
    if words & AVOID_WORDS and not _STAY_ON.search(text) and not MOVE_AWAY.match(text):
        aways = by.get("away", [])
        if not aways:
            gaps.append("the distance it keeps: away('<what moves>', '<object>', cm=<distance>) "
                        "measures it")
        elif pushed and all(is_end_effector(a.subject) for a in aways):
            gaps.append(f"the pushed object's distance: away('{pushed} ...', "
                        "'<object>') — the pushed object, not the gripper")
    if _STAY_ON.search(text):
        if not by.get("passed_on"):
            gaps.append("the side it keeps while passing: passed_on('gripper', '<object>', "
                        "'<side>') measures the path, on(...) only where it ends")
        for cond in by.get("on", []):
            if cond.other and cond.other != "table":
                gaps.append(f"on({cond.subject!r}, {cond.other!r}, ...) says it ends beside "
                            f"the {cond.other}, but it only passes it: replace it by "
                            f"passed_on({cond.subject!r}, {cond.other!r}, '<side>')")
    if pushed and not any(c.helper != "away" and pushed in _words(c.subject)
                          for c in (*conditions, *later)):
        gaps.append(f"where the pushed object ends: moved('{pushed} ...') or "
                    f"on('{pushed} ...', 'table', '<place>') — the pushed object, "
                    "not the gripper")
    return gaps


def intent_gaps(code: str) -> list[ClauseGap]:
    """The post-condition gaps of the planner's ``code`` (kind "post-condition", ``words``
    the sub-task and what its conditions leave out); empty when the code does not parse."""
    planned = subtask_conditions(code)
    if not planned:
        return []
    if not any(c for _, c in planned):  # no post-condition at all: the run claims success
        return []                         # when no sub-task fails; nothing to measure here
    gaps = []
    for i, (subtask, conds) in enumerate(planned):
        if not subtask or _NO_MOTION.match(subtask.lower().strip()):
            continue
        later = tuple(c for _, cs in planned[i + 1:] for c in cs)
        gaps += [ClauseGap("post-condition", f"after composer({subtask!r}): {gap}")
                 for gap in subtask_gaps(subtask, conds, later)]
    return gaps


def intent_message(gaps: list[ClauseGap]) -> str:
    """The correction the planner reads for post-condition gaps ("" when there are none)."""
    if not gaps:
        return ""
    return ("Your expect(...) post-conditions do not measure every part of the plan: "
            + "; ".join(g.words for g in gaps)
            + ". Add those conditions to the expect(...) after that sub-task.")


__all__ = ["Condition", "intent_gaps", "intent_message", "subtask_conditions", "subtask_gaps"]
