"""Objects named by their relation, grounded by geometry before the planner reads the words.

People name an object by where it is: "the leftmost block", "the block closest to the robot",
"the second block from the right", "the block next to the green block". The planner sees the
scene's object names but not where they are, so the bundled 1.5B model guessed a colour for
such a phrase, or passed the words on to map programs that picked by the wrong index or
named blocks the scene lacks (dev records). Here each such phrase is matched, its candidates
(the scene's objects of that kind: "block" → every "... block"; "side" and "corner" of the
table → the table's named places, :mod:`voxposer.places`) are scored by the relation on their
detected positions (a place: its point), and the phrase is replaced by the winner's name — when it wins
by at least :data:`MIN_MARGIN_M`; otherwise the words stay as said and the model reads them.

Directions are the LMP API's (:mod:`voxposer.lmp.api`): front +x, back −x, right +y, left −y.
"The robot" (and "you", "me") is the robot's detected points (how near: the
:data:`ROBOT_NEAR_PERCENTILE` of the distances to them); another object is its detected centre. Positions in metres.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import VoxPoserError
from voxposer.lmp.object_view import detection_field
from voxposer.lmp.sides import direction_sign
from voxposer.lmp.transcript import Transcript
from voxposer.perception.names import normalize_name
from voxposer.places import PLACES

#: the winner of a relation must beat the runner-up by this much [m] to be named.
MIN_MARGIN_M: Final = 0.02
#: how near something is to the robot: this percentile of its distances to the robot's points
#: (the nearest of them but a few: a handful of stray points labelled robot by a noisy
#: perception made a far side of the table "nearest the robot" when the nearest point counted).
ROBOT_NEAR_PERCENTILE: Final = 10.0
#: kinds of object a relation may pick among (the last word of a scene name).
KINDS: Final = ("block", "line", "cube")
#: the direction words a relation reads (their axes and signs: :func:`voxposer.lmp.sides.direction_sign`).
_DIRECTIONS: Final = ("left", "right", "front", "back", "rear")
_SUPERLATIVES: Final = tuple(f"{d}most" for d in _DIRECTIONS)
_ORDINALS: Final = {"first": 0, "1st": 0, "second": 1, "2nd": 1, "third": 2, "3rd": 2,
                    "fourth": 3, "4th": 3}
_ROBOT_WORDS: Final = ("the robot", "you", "me", "the robot arm", "the arm", "the robot's base")
_NEAR: Final = ("nearest", "closest", "next", "beside", "by")
_FAR: Final = ("farthest", "furthest", "away")
#: the table's places a relation may pick among: "side" → its sides, "corner" → its corners.
_PLACE_KINDS: Final = ("side", "corner")
#: each table place's point [m], shape (3,), on the table (z 0).
_PLACE_POINTS: Final = {p.name: np.array([*p.point, 0.0]) for p in PLACES.values()}


@dataclass(frozen=True)
class Grounding:
    """One phrase replaced: the words said, the object meant, the relation's margin [m]."""

    phrase: str
    name: str
    margin: float

    def to_json(self) -> dict[str, Any]:
        return {"phrase": self.phrase, "name": self.name, "margin_m": round(self.margin, 3)}


Locate = Callable[[str], NDArray[np.float64]]


def _patterns(refs: str) -> list[re.Pattern[str]]:
    kind = r"(?P<kind>" + "|".join(KINDS) + r")"
    dirs = r"(?P<dir>" + "|".join(_DIRECTIONS) + r")"
    sup = r"(?P<sup>" + "|".join(_SUPERLATIVES) + r")"
    nth = r"(?P<nth>" + "|".join(_ORDINALS) + r")"
    rel = r"(?P<rel>" + "|".join(_NEAR + _FAR) + r")"
    that = r"(?:(?:that is|that's|which is) )?"
    places = r"(?P<kind>" + "|".join(_PLACE_KINDS) + r")"
    return [re.compile(p, re.IGNORECASE) for p in (
        rf"\bthe {sup} {kind}\b",
        rf"\bthe {kind} {that}(?:(?:farthest|furthest|most) to|(?:on|at) the (?:far|very)) "
        rf"(?:the )?{dirs}\b",
        rf"\bthe {nth} {kind} (?:from|counting from|counted from) the {dirs}(?: side| end)?\b",
        rf"\bthe {kind} {that}{rel}(?: to| from)? (?P<ref>{refs})\b",
        rf"\bthe {rel} {kind} (?:to|from) (?P<ref>{refs})\b",
        rf"\bthe {places} of the table {that}{rel}(?: to| from)? (?P<ref>{refs})\b",
        rf"\bthe {rel} {places} of the table (?:to|from) (?P<ref>{refs})\b",
    )]


def _along(direction: str, where: NDArray[np.float64]) -> NDArray[np.float64]:
    """How far each of ``where`` (N, 3) [m] lies toward ``direction``."""
    axis_sign = direction_sign(direction)
    assert axis_sign is not None, direction
    return axis_sign[1] * where[:, axis_sign[0]]


def _choice(match: re.Match[str], where: NDArray[np.float64], locate: Locate,
            robot: NDArray[np.float64] | None, ref_name: str | None) -> tuple[int, float] | None:
    """The candidate ``match``'s relation picks (an index into ``where``, the candidates'
    centres, shape (N, 3) [m]) and by how much it is singled out [m]; None when the
    relation's reference cannot be placed."""
    g = {k: (v.lower() if v else v) for k, v in match.groupdict().items()}
    direction = g.get("sup") or g.get("dir")
    if g.get("nth") is not None:
        toward = _along(direction or "left", where)
        order = np.argsort(-toward)  # the first is the one farthest toward the direction
        k = _ORDINALS[g["nth"]]
        if k >= len(order):
            return None
        gaps = [abs(toward[order[k]] - toward[order[j]]) for j in (k - 1, k + 1)
                if 0 <= j < len(order)]
        return int(order[k]), float(min(gaps))
    if direction:
        score = _along(direction, where)
    else:
        if g["ref"] in _ROBOT_WORDS:
            if robot is None or len(robot) == 0:
                return None
            d = np.array([np.percentile(np.linalg.norm(robot[:, :2] - w[:2], axis=1),
                                        ROBOT_NEAR_PERCENTILE) for w in where])
        else:
            assert ref_name is not None
            d = np.linalg.norm(where[:, :2] - locate(ref_name)[:2], axis=1)
        score = d if g["rel"] in _FAR else -d
    order = np.argsort(-score)
    return int(order[0]), float(score[order[0]] - score[order[1]])


def ground_references(text: str, names: Sequence[str], locate: Locate,
                      robot_points: Callable[[], NDArray[np.float64] | None]
                      ) -> tuple[str, list[Grounding]]:
    """``text`` with each object named by relation replaced by "the <its scene name>".

    Args:
        text: the instruction.
        names: the scene's object names.
        locate: name → its detected centre [m], shape (3,).
        robot_points: the robot's detected points [m], shape (N, 3) (None: not seen); asked
            only for a relation to the robot.

    Returns:
        the text and what was replaced, in the text's order.
    """
    objects = sorted((n for n in names if normalize_name(n) not in ("robot", "gripper", "table")),
                     key=len, reverse=True)
    refs = "|".join([re.escape(w) for w in _ROBOT_WORDS] + [f"the {re.escape(n)}" for n in objects])
    found: list[tuple[int, int, Grounding]] = []
    robot: NDArray[np.float64] | None = None
    for pattern in _patterns(refs):
        for match in pattern.finditer(text):
            if any(a < match.end() and match.start() < b for a, b, _ in found):
                continue
            ref = (match.groupdict().get("ref") or "").lower() or None
            ref_name = next((n for n in objects if ref == f"the {n.lower()}"), None)
            kind = match.group("kind").lower()
            if kind in _PLACE_KINDS:
                cands = [p.name for p in PLACES.values() if p.kind == kind]
                spot = _PLACE_POINTS.__getitem__
            else:
                cands = [n for n in objects if n.lower().split()[-1] == kind and n != ref_name]
                spot = locate
            if len(cands) < 2:
                continue
            if robot is None and ref in _ROBOT_WORDS:
                robot = robot_points()
            try:
                where = np.array([spot(n) for n in cands], dtype=np.float64)
                picked = _choice(match, where, locate, robot, ref_name)
            except VoxPoserError:  # a candidate or the reference not seen: the words stay
                continue
            if picked is None or picked[1] < MIN_MARGIN_M:
                continue
            found.append((match.start(), match.end(),
                          Grounding(match.group(0), cands[picked[0]], picked[1])))
    found.sort(key=lambda f: f[0])
    for start, end, g in reversed(found):
        text = f"{text[:start]}the {g.name}{text[end:]}"
    return text, [g for _, _, g in found]


def grounded_instruction(instruction: str, scene: Any, transcript: Transcript) -> str:
    """``instruction`` with its objects named by relation grounded on ``scene`` (an
    :class:`~voxposer.lmp.scene.Scene`: ``detect(name)`` gives ``position`` and ``points`` in
    metres); each replacement recorded as a ``reference_grounded`` transcript event."""
    names = tuple(scene.object_names)

    def robot_points() -> NDArray[np.float64] | None:
        if "robot" not in names:
            return None
        try:
            points = detection_field(scene.detect("robot"), "points")
            return np.asarray(points, dtype=np.float64).reshape(-1, 3)
        except VoxPoserError:
            return None

    text, done = ground_references(
        instruction, names,
        lambda n: np.asarray(detection_field(scene.detect(n), "position"), dtype=np.float64),
        robot_points)
    for g in done:
        transcript.write("reference_grounded", instruction=instruction, **g.to_json())
    return text


__all__ = ["MIN_MARGIN_M", "Grounding", "ground_references", "grounded_instruction"]
