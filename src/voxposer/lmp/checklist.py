"""The clause checklist: every clause of an instruction must reach some planned sub-task.

A small model drops clauses ("move above the cyan block, and please avoid the red one" planned
as just "move above the cyan block"). Before the planner's code runs (it has side effects), the
runtime reads the ``composer('...')`` sub-tasks out of it (:func:`planned_subtasks`) and checks
that what the instruction names is carried by some of them (:func:`clause_gaps`):

- every colour word (the object it names, "the red one");
- every number (distances, "7cm");
- a speed clause ("slowly", "at a quarter of the speed", "as fast as is safe") by some speed
  word, an avoidance clause ("avoid", "keep clear of", "without touching") by some avoidance
  word, since the sub-task may say it in other words;
- and no sub-task is a constraint alone ("move at faster speed whenever you are within 3cm of
  the green block" after "go to the back left corner"): a constraint must share the sub-task
  of the motion it constrains, or the executor has nowhere to go while it applies.

The checks are lexical on purpose: cheap, predictable, and they can only ask the model once
more (the runtime retries the planner once with the gaps listed, then runs the better plan).
"""

from __future__ import annotations

import ast
import re
from typing import Final, NamedTuple

from voxposer.catalog import COLOR_NAMES
from voxposer.perception.names import normalize_name

#: words that carry a speed clause; any one of them in a sub-task carries it.
SPEED_WORDS: Final = frozenset({
    "slow", "slowly", "slower", "slowest", "fast", "faster", "fastest", "quick", "quickly",
    "quicker", "speed", "speeds", "pace", "velocity", "gently", "carefully", "rapidly", "hurry",
    "leisurely", "swiftly", "crawl",
})
#: words that carry an avoidance clause.
AVOID_WORDS: Final = frozenset({
    "avoid", "avoiding", "away", "clear", "distance", "apart", "bump", "bumping", "hit",
    "hitting", "touch", "touching", "collide", "colliding", "around", "steer",
})
#: a sub-task whose motion is leaving an object ("move away from the pink block"): there
#: "away" says where the hand goes, not a distance the path keeps.
MOVE_AWAY: Final = re.compile(
    r"^(?:then\s+|and\s+|finally\s+)?(?:move|go|get|back|step|pull|retreat)\s+(?:the\s+"
    r"(?:gripper|hand|end\s+effector)\s+)?(?:back\s+)?away\s+from\s+(?:the\s+)?"
    r"(?P<obj>[a-z ]+?)\.?$")
#: a sub-task that pushes an object: ``words``, the words after the verb (and "the"), which
#: begin with the pushed object's name.
PUSH_SUBTASK: Final = re.compile(r"^\s*(?:then\s+|and\s+|first\s+)?(?:push|slide|nudge|shove|"
                                 r"pushing|sliding)\s+(?:the\s+)?(?P<words>[a-z ]+)", re.I)
#: how a sub-task that moves the hand begins (after "then", "and" or "first"): a verb of motion,
#: or a verb whose object is the hand ("bring the gripper to …"); one pattern for every plan
#: completion that looks for the hand's motions.
HAND_MOTION_START: Final = (
    r"^\s*(?:then\s+|and\s+|first\s+)?(?:move|go|get|head|travel|reach|navigate|steer|return|"
    r"proceed|make\s+your\s+way|(?:bring|take|guide|position)\s+(?:the\s+|your\s+)?"
    r"(?:hand|gripper|end[\s-]effector|arm))\b")
#: :data:`HAND_MOTION_START` compiled, case-insensitive.
HAND_MOTION: Final = re.compile(HAND_MOTION_START, re.I)
#: a table part a speed applies in, said in words: (part).
REGION_SAID: Final = re.compile(r"\b(?:in|inside|over|above|across|through|within)\s+the\s+"
                            r"((?:[a-z]+\s+){0,2}(?:side|corner|half|part|edge))\s+of\s+the\s+table")
#: the zone around an object a speed applies in: (cm, object words).
NEAR_SAID: Final = re.compile(r"\b(?:within|closer\s+than|inside)\s+(\d+(?:\.\d+)?)\s*(?:cm|centimet"
                          r"(?:er|re)s?)\s+(?:of|from|to)\s+the\s+([a-z ]+)")
_NUMBER: Final = re.compile(r"(?<![\w.])(\d+(?:\.\d+)?)")
#: how a sub-task that only constrains begins ("keep at least…", "move at faster speed…").
_CONSTRAINT_ONLY: Final = re.compile(
    r"^(?:and |then |also )?(?:keep|keeping|stay|staying|avoid|avoiding|while|when|whenever|"
    r"remain|never|do not|don't|be|"
    r"(?:move|moving|go|going|travel)\s+(?:at|with|more|less|slowly|slower|faster|quickly|fast|"
    r"slow|carefully|gently))\b")
_DESTINATION: Final = re.compile(r"\b(?:to|into|onto|towards?|above|over|grasp|push|pull)\b")


class ClauseGap(NamedTuple):
    """What the instruction carries and no sub-task does: ``kind`` (colour, number, speed,
    avoidance) and the instruction's ``words``."""

    kind: str
    words: str

    def describe(self) -> str:
        """The gap in words, as the model reads it."""
        return f"the {self.kind} {self.words!r}"


def planned_subtasks(code: str) -> list[str] | None:
    """The string arguments of the ``composer(...)`` calls in ``code``, in order (None when the
    code does not parse; f-strings contribute their literal parts)."""
    try:
        tree = ast.parse(code)
    except SyntaxError:
        return None
    out: list[str] = []
    for node in ast.walk(tree):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                and node.func.id == "composer" and node.args):
            arg = node.args[0]
            if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                out.append(arg.value)
            elif isinstance(arg, ast.JoinedStr):
                out.append("".join(v.value for v in arg.values
                                   if isinstance(v, ast.Constant) and isinstance(v.value, str)))
    return out


def _words(text: str) -> set[str]:
    return set(re.findall(r"[a-z]+", normalize_name(text)))


def says_speed(text: str) -> bool:
    """Whether ``text`` (a sub-task's words) says a speed: one of :data:`SPEED_WORDS`."""
    return bool(set(re.findall(r"[a-z]+", text.lower())) & SPEED_WORDS)


def _numbers(text: str) -> set[float]:
    return {float(n) for n in _NUMBER.findall(text)}


def clause_gaps(instruction: str, subtasks: list[str]) -> list[ClauseGap]:
    """What ``instruction`` names that none of ``subtasks`` carries (empty: all covered)."""
    said, planned = _words(instruction), set().union(*(_words(s) for s in subtasks))
    gaps = [ClauseGap("colour", c) for c in COLOR_NAMES if c in said and c not in planned]
    planned_numbers = set().union(*(_numbers(s) for s in subtasks))
    gaps += [ClauseGap("number", f"{n:g}") for n in sorted(_numbers(instruction))
             if n not in planned_numbers]
    for kind, vocabulary in (("speed clause", SPEED_WORDS), ("avoidance clause", AVOID_WORDS)):
        used = sorted(said & vocabulary)
        if used and not planned & vocabulary:
            gaps.append(ClauseGap(kind, " ".join(used)))
    if len(subtasks) > 1:
        gaps += [ClauseGap("constraint without a motion", s) for s in subtasks
                 if constraint_only(s)]
    return gaps


def constraint_only(subtask: str) -> bool:
    """Whether ``subtask`` states only a constraint (a speed, a distance to keep) with no
    motion of its own ("keep at least 9cm away from the green block")."""
    text = " ".join(subtask.lower().split())
    if not _CONSTRAINT_ONLY.match(text):
        return False
    head = re.split(r"\b(?:while|when|whenever|within|from|of)\b", text)[0]
    return not _DESTINATION.search(head) or text.startswith(("keep", "stay", "avoid", "while",
                                                            "when", "remain", "never"))


def checklist_message(instruction: str, gaps: list[ClauseGap]) -> str:
    """The correction the planner reads: which parts of ``instruction`` no sub-task carries."""
    missing = [g for g in gaps if g.kind != "constraint without a motion"]
    alone = [g for g in gaps if g.kind == "constraint without a motion"]
    parts = []
    if missing:
        parts.append(f"Your plan leaves out part of the instruction {instruction!r}: "
                     f"{', '.join(g.describe() for g in missing)} appear(s) in no composer(...) "
                     "sub-task. Every part of the instruction (each object, distance, speed and "
                     "thing to avoid or stay on) must be in the words of some sub-task.")
    if alone:
        parts.append(f"The sub-task(s) {', '.join(repr(g.words) for g in alone)} only state a "
                     "constraint: put each into the sub-task of the motion it constrains, as "
                     "one composer call ('move to ... while ...').")
    return " ".join(parts) + " Keep the other sub-tasks as they are."
