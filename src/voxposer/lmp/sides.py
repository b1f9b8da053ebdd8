"""Side words ("the far left corner of the table", "rear", "top-left") → world directions.

The programs name parts of objects in words people use; :func:`parse_side` turns a phrase
into ``{axis: sign}`` in the world frame of :mod:`voxposer.geometry.voxel_grid` (metres):
front = +x, back = −x, right = +y, left = −y, up = +z. The robot stands at the back (−x); the
words are read as seen by a person at the front of the table facing the robot, so:

* **far** words (far, further, farthest, away, distant…) mean the back and **near** words
  (near, closer, nearest…) the front: "the far end" is the back side, "the near left corner" the
  front left corner. Beside the robot they are relative to it: "nearest to the robot", "next to
  the robot", "the robot's side" are the back, "away from the robot" the front.
  A far/near word only emphasises when the phrase names front/back itself ("the far left corner
  at the back"), when it directly precedes left/right without a corner ("the far left" is the
  left side), or when it is a preposition before something other than the robot ("close to the
  back" is the back).
* on a **surface** (``point_on``, ``region_mask``), top/upper and bottom/lower next to left/right
  read as on a page seen from the front: "top-left corner" is the back left corner, "lower
  right" the front right corner. Elsewhere (and with front/back words) they stay up/down.
* hyphens and glued words ("back-left", "topleft"), "-most" endings ("leftmost"), "'s" and filler
  words ("the", "of", "table", "corner", "side", "end"…) are fine; the object's own name may
  appear ("the left side of the blue block").

Contradictions (front and back, left and right, top and bottom, far and near) stay a
:class:`SideError`, and so does any other word; the message lists every accepted word, since the
language model reads it when it retries.
"""

from __future__ import annotations

import re
from typing import Final

from voxposer.errors import VoxPoserError

#: (axis, sign, words): the strong direction words. Axis 0 = x, 1 = y, 2 = z.
_GROUPS: Final[tuple[tuple[int, int, tuple[str, ...]], ...]] = (
    (0, 1, ("front", "forward", "forwards", "fore", "ahead", "+x", "x")),
    (0, -1, ("back", "behind", "rear", "backward", "backwards", "-x")),
    (1, 1, ("right", "+y", "y")),
    (1, -1, ("left", "-y")),
    (2, 1, ("top", "upper", "above", "over", "up", "upward", "upwards", "on", "+z", "z")),
    (2, -1, ("bottom", "lower", "below", "under", "underneath", "beneath", "down", "downward",
             "downwards", "-z")),
)
_GROUP_NAMES: Final = ("front/+x", "back/-x", "right/+y", "left/-y", "up/+z", "down/-z")
#: Word → (axis, sign) of every strong direction word.
DIRECTION_WORDS: Final[dict[str, tuple[int, int]]] = {
    w: (axis, sign) for axis, sign, words in _GROUPS for w in words}
#: Up/down words that read as back/front beside left/right on a surface ("top-left corner").
PAGE_WORDS: Final = frozenset({"top", "upper", "bottom", "lower"})
FAR_WORDS: Final = ("far", "farther", "further", "farthest", "furthest", "distant", "away")
NEAR_WORDS: Final = ("near", "nearer", "nearest", "close", "closer", "closest")
#: Words that mean "near" only before "the robot" ("next to the robot").
ROBOT_NEAR_WORDS: Final = ("next", "by", "beside")
ROBOT_WORDS: Final = frozenset({"robot", "robots"})
CENTRE_WORDS: Final = ("center", "centre", "central", "middle", "mid", "half")
FILLER_WORDS: Final = (
    "the", "a", "an", "of", "at", "in", "to", "towards", "toward", "from", "and", "its", "it",
    "this", "that", "which", "is", "table", "tabletop", "corner", "corners", "side", "sides",
    "end", "ends", "edge", "edges", "face", "faces", "part", "portion", "region", "area",
    "surface", "zone", "section", "quadrant", "border", "rim", "hand", "most", "very", "extreme",
    "spot", "point", "place", "position", "location", "axis", "bit", "little", "slightly",
    "somewhat", "just", "more", "further", "farther", "direction", "way", "all",
)
_AXIS_TOKENS: Final = frozenset({"+x", "-x", "+y", "-y", "x", "y"})
_PREPOSITIONS: Final = frozenset({"to", "from", "the", "a", "an", "of"})
_SKIP_BEFORE_ROBOT: Final = frozenset({"the", "to", "from", "of", "a", "its"})
_ROBOT_SIDE: Final = frozenset({"side", "end", "edge"})
_IGNORED: Final = frozenset(CENTRE_WORDS) | frozenset(FILLER_WORDS) | {""}
_KNOWN: Final = (frozenset(DIRECTION_WORDS) | frozenset(FAR_WORDS) | frozenset(NEAR_WORDS)
                 | ROBOT_WORDS | _IGNORED)
_AXIS_NAMES: Final = ("x", "y", "z")
_SIGN_WORDS: Final = {(0, 1): "front", (0, -1): "back", (1, 1): "right", (1, -1): "left",
                      (2, 1): "top", (2, -1): "bottom"}


class SideError(VoxPoserError, ValueError):
    """A side/direction phrase has a word the API does not understand, or contradicts itself."""


def accepted_words() -> str:
    """Every word :func:`parse_side` accepts, grouped by meaning (the error messages' list)."""
    groups = "; ".join(f"{name}: {', '.join(words)}"
                       for name, (_, _, words) in zip(_GROUP_NAMES, _GROUPS, strict=True))
    return (f"{groups}; far words (the back, or the front 'away from the robot'): "
            f"{', '.join(FAR_WORDS)}; near words (the front, or the back 'near the robot'; also "
            f"{', '.join(ROBOT_NEAR_WORDS)} before 'the robot'): {', '.join(NEAR_WORDS)}; "
            f"centre: {', '.join(CENTRE_WORDS)}; ignored: {', '.join(FILLER_WORDS)}, robot; "
            "hyphens ('top-left') and '-most' endings ('leftmost') are fine; on a surface, "
            "top/upper and bottom/lower beside left/right mean back and front ('top-left corner' "
            "= 'back left corner')")


def _split_glued(word: str) -> list[str] | None:
    """``"backleft"`` → ``["back", "left"]``; None when ``word`` is not known words glued."""
    for cut in range(2, len(word) - 1):
        head, tail = word[:cut], word[cut:]
        if head in _KNOWN and head not in _IGNORED:
            rest = [tail] if tail in _KNOWN else _split_glued(tail)
            if rest is not None:
                return [head, *rest]
    return None


def _normalise(word: str) -> list[str]:
    """One raw word as known words (the "-most" ending dropped, glued words split), or itself."""
    if word in _KNOWN:
        return [word]
    if word.endswith("most") and word[:-4] in _KNOWN:
        return [word[:-4]]
    return _split_glued(word) or [word]


def side_words(side: str, name: str = "") -> list[str]:
    """The words of ``side``, lower case, without punctuation, "'s", hyphens between letters, and
    without the object's own ``name`` ("blue block") where it appears as a phrase."""
    text = re.sub(r"['’]s\b", "", str(side).strip().lower())
    text = re.sub(r"(?<=[a-z])-(?=[a-z])", " ", text)
    raw = [w for w in re.split(r"[\s,/_.;:!?()'\"’]+", text) if w]
    own = str(name).lower().replace("_", " ").split()
    if own:
        k, kept = 0, []
        while k < len(raw):
            if raw[k:k + len(own)] == own:
                k += len(own)
                continue
            kept.append(raw[k])
            k += 1
        raw = kept
    return [w for word in raw for w in _normalise(word)]


def splits_at_centre(side: str) -> bool:
    """Whether ``side`` asks for a centre split ("half", or an axis token such as "-y") rather
    than a named table place."""
    words = set(side_words(side))
    return "half" in words or bool(words & _AXIS_TOKENS)


def _robot_relative(words: list[str], used: set[int]) -> int | None:
    """The x sign that "near/away from the robot" phrases give (−1: back, +1: front), marking the
    words they use; None when the phrase has none."""
    sign: int | None = None
    for i, word in enumerate(words):
        if word not in ROBOT_WORDS:
            continue
        j = i - 1
        while j >= 0 and words[j] in _SKIP_BEFORE_ROBOT:
            j -= 1
        here = None
        if j >= 0 and words[j] in NEAR_WORDS + ROBOT_NEAR_WORDS:
            here = -1
            used.add(j)
        elif j >= 0 and words[j] in FAR_WORDS:
            here = 1
            used.add(j)
        elif i + 1 < len(words) and words[i + 1] in _ROBOT_SIDE:
            here = -1
        if here is not None:
            if sign is not None and sign != here:
                raise SideError("side names both the end near the robot (back) and the end away "
                                "from it (front); name one")
            sign = here
    return sign


def _weak_sign(words: list[str], i: int, has_corner: bool, side: str) -> int | None:
    """The x sign a far/near word at ``words[i]`` gives (None: it only emphasises)."""
    word = words[i]
    nxt = words[i + 1] if i + 1 < len(words) else ""
    if nxt in _PREPOSITIONS:
        if word in FAR_WORDS:
            raise SideError(f"{word!r} from something other than the robot in {side!r} has no "
                            "side; name the side itself ('front', 'back', 'left', 'right')")
        return None  # "close to the back": the back
    if DIRECTION_WORDS.get(nxt, (0, 0))[0] == 1 and not has_corner:
        return None  # "the far left": the left side
    return -1 if word in FAR_WORDS else 1


def _set(out: dict[int, int], axis: int, sign: int, side: str) -> None:
    if out.get(axis, sign) != sign:
        raise SideError(
            f"side {side!r} names both {_SIGN_WORDS[(axis, 1)]!r} and {_SIGN_WORDS[(axis, -1)]!r} "
            f"({_AXIS_NAMES[axis]} axis); name one per axis, e.g. 'back left corner'")
    out[axis] = sign


def parse_side(side: str, *, surface: bool = False, name: str = "") -> dict[int, int]:
    """Axis → sign (+1/−1) for a phrase such as "back left", "the far end", "+y" (module docs).

    Args:
        side: the phrase; centre and filler words alone give ``{}`` (the centre).
        surface: the phrase names a part of a top surface (``point_on``, ``region_mask``), so
            top/bottom beside left/right read as back/front ("top-left corner").
        name: the object's name, allowed in the phrase ("the left side of the blue block").

    Returns:
        ``{axis: sign}`` with axis 0 = x (front +1, back −1), 1 = y (right +1, left −1),
        2 = z (up +1, down −1).

    Raises:
        SideError: an unknown word (the message lists the accepted ones), or a contradiction.
    """
    words = side_words(side, name)
    used: set[int] = set()
    robot_x = _robot_relative(words, used)
    has_corner = bool({"corner", "corners"} & set(words))
    out: dict[int, int] = {}
    weak: set[int] = set()
    page_only_z = True
    for i, word in enumerate(words):
        if i in used or word in _IGNORED or word in ROBOT_WORDS:
            continue
        if word in DIRECTION_WORDS:
            axis, sign = DIRECTION_WORDS[word]
            _set(out, axis, sign, side)
            page_only_z &= axis != 2 or word in PAGE_WORDS
        elif word in FAR_WORDS or word in NEAR_WORDS:
            sign_or_none = _weak_sign(words, i, has_corner, side)
            if sign_or_none is not None:
                weak.add(sign_or_none)
        else:
            raise SideError(f"unknown side word {word!r} in {side!r}; accepted: {accepted_words()}")
    if robot_x is not None:
        _set(out, 0, robot_x, side)
    if 0 not in out and weak:
        if len(weak) > 1:
            raise SideError(f"side {side!r} is both far (back) and near (front); name one")
        out[0] = weak.pop()
    if surface and 2 in out and 1 in out and 0 not in out and page_only_z:
        out[0] = -out.pop(2)  # on a page seen from the front: top = the far (back) edge
    return out


def direction_sign(word: str) -> tuple[int, int] | None:
    """(axis, sign) of a single direction word ("rear", "leftmost"); None for anything else."""
    words = side_words(word)
    if len(words) != 1 or words[0] not in DIRECTION_WORDS:
        return None
    return DIRECTION_WORDS[words[0]]
