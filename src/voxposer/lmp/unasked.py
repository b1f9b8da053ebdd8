"""What a plan does that its instruction never asks: the clause checklist's other half.

:mod:`voxposer.lmp.checklist` catches clauses the plan drops; a small model also *adds* to a
plan. Read from dev records of reworded "push the X to the P and keep it away from the Z"
instructions, the planner

- grasped, carried and released the block it was asked to push (a grasp the instruction never
  asks);
- made the object to keep away from a destination of its own ("move around the pink block"),
  leaving the push itself unconstrained;
- pushed the block on to a place the instruction never names ("… to the back side of the
  table" after "… to the right side of the table").

:func:`unasked_gaps` names a grasp or a place; like the checklist's gaps they can only ask the
model once more (:class:`voxposer.lmp.plan_review.PlanReview`). A motion to what is to be
avoided (:func:`to_avoided`) is mended without asking (:mod:`voxposer.lmp.plan_avoid`): asked,
the model answered with that sub-task alone, a post-condition added. The checks are lexical and
conservative: an instruction with any grasping word, or one that names no table place in the
places' own words, is never sent back for these.
"""

from __future__ import annotations

import re
from typing import Final

from voxposer.catalog import COLOR_NAMES
from voxposer.lmp.checklist import AVOID_WORDS, MOVE_AWAY, ClauseGap
from voxposer.perception.names import normalize_name
from voxposer.places import PLACES

UNASKED_GRASP: Final = "grasp the instruction does not ask"
UNNAMED_PLACE: Final = "place the instruction does not name"
#: the gap kinds of this module.
KINDS: Final = (UNASKED_GRASP, UNNAMED_PLACE)

#: a sub-task that takes hold of an object or lets go of it.
_GRASPING: Final = re.compile(r"\b(?:grasp|grab|pick|carry|release|let go)\b")
#: instruction words after which a grasp may be meant (conservative: any one of them is enough).
_MAY_GRASP: Final = re.compile(
    r"\b(?:grasp\w*|grab\w*|grip\w*|pick\w*|carr\w+|lift\w*|hold\w*|drop\w*|releas\w*|let go|"
    r"place|put|bring|take|fetch|get|hand|transport\w*|pour\w*|open\w*|close\w*|shut\w*)\b")
#: the table's places in their own words, longest first ("back left corner" before "left").
_PLACE_NAMES: Final = tuple(sorted((p.name for p in PLACES.values()), key=len, reverse=True))
#: an object named by colour: (colour, noun).
_OBJECT: Final = re.compile(r"\b(" + "|".join(sorted(COLOR_NAMES, key=len, reverse=True))
                            + r")\s+([a-z]+)")


def _text(s: str) -> str:
    return " ".join(normalize_name(s).split())


def _places(text: str) -> set[str]:
    found, rest = set(), text
    for name in _PLACE_NAMES:
        if name in rest:
            found.add(name)
            rest = rest.replace(name, " ")
    return found


def named_places(text: str) -> set[str]:
    """The table places ``text`` names in the places' own words ("back left corner of the
    table")."""
    return _places(_text(text))


def avoided_objects(instruction: str) -> set[str]:
    """The objects ``instruction`` names only to keep away from ("keep it away from the pink
    block", "avoiding the blue block"): named once, right after an avoidance word, and not
    referred to after that ("… stay away from the red block, then hover over it")."""
    text = _text(instruction)
    named = [(m.start(), f"{m.group(1)} {m.group(2)}") for m in _OBJECT.finditer(text)]
    out = set()
    for start, name in named:
        if sum(n == name for _, n in named) != 1:
            continue
        before = re.findall(r"[a-z]+", text[:start])[-4:]
        later = re.findall(r"[a-z]+", text[start + len(name):])
        said = AVOID_WORDS.intersection(before) or {"near", "berth"}.intersection(before) \
            or "berth" in later[:3]  # "give the blue block a wide berth"
        if said and not {"it", "them", "there"}.intersection(later):
            out.add(name)
    return out


def to_avoided(subtask: str, avoided: str) -> bool:
    """Whether ``subtask`` moves to or around ``avoided`` ("move around the pink block"): it
    names that object and no other object or table place, and does not leave it."""
    text = _text(subtask)
    others = {f"{c} {n}" for c, n in _OBJECT.findall(text)} - {avoided}
    return avoided in text and not others and not _places(text) and not MOVE_AWAY.match(text)


def unasked_gaps(instruction: str, subtasks: list[str]) -> list[ClauseGap]:
    """The sub-tasks of a plan that grasp or go to a table place ``instruction`` does not ask
    (empty: none). A motion to what is to be avoided is not sent back but mended
    (:mod:`voxposer.lmp.plan_avoid`)."""
    said = _text(instruction)
    gaps: list[ClauseGap] = []
    if not _MAY_GRASP.search(said):
        gaps += [ClauseGap(UNASKED_GRASP, s) for s in subtasks if _GRASPING.search(_text(s))]
    named = _places(said)
    if named:
        gaps += [ClauseGap(UNNAMED_PLACE, s) for s in subtasks if _places(_text(s)) - named]
    return gaps


def unasked_message(gaps: list[ClauseGap]) -> str:
    """The correction the planner reads for :func:`unasked_gaps` (empty: none of them)."""
    def listed(kind: str) -> str:
        return ", ".join(repr(g.words) for g in gaps if g.kind == kind)
    parts = []
    if listed(UNASKED_GRASP):
        parts.append(f"The instruction asks no grasp, but {listed(UNASKED_GRASP)} grasp(s) or "
                     "release(s) an object: leave such sub-tasks out (a push moves an object "
                     "with the open gripper).")
    if listed(UNNAMED_PLACE):
        parts.append(f"{listed(UNNAMED_PLACE)} go(es) to a place of the table the instruction "
                     "does not name: use only the places the instruction names.")
    return " ".join(parts)


__all__ = ["KINDS", "UNASKED_GRASP", "UNNAMED_PLACE", "avoided_objects", "named_places",
           "to_avoided", "unasked_gaps", "unasked_message"]
