"""Lenient object names, with the one synonym table: "the Grey cube" is the "gray block".

Every stage that turns words into scene objects (the programs' ``parse_query_obj``/``detect``,
perception's ``detect``, scene occupancy's "the entity itself") goes through
:func:`match_name`; nothing else keeps synonyms.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from typing import Final

from voxposer.errors import UnknownObjectError

#: Word-level synonyms applied before matching names.
_SYNONYMS: Final = {
    "grey": "gray", "cube": "block", "box": "block", "end effector": "gripper",
    "ee": "gripper", "hand": "gripper", "robot hand": "gripper", "topmost": "top",
    "bottommost": "bottom", "second to the top": "middle", "second to the bottom": "middle",
    "lowest": "bottom", "highest": "top", "desk": "table", "tabletop": "table",
    "table top": "table", "cupboard": "cabinet",
}


def normalize_name(name: str) -> str:
    """Lower case, single spaces, no article/possessive, synonyms replaced."""
    return _normalized(str(name))


@functools.lru_cache(maxsize=4096)
def _normalized(name: str) -> str:
    """:func:`normalize_name` of a string, remembered: every replan matches the scene's names
    against each query again (some hundred names a step, each a few dozen regex passes)."""
    key = re.sub(r"[\s_]+", " ", name).strip().lower()
    key = re.sub(r"^(the|a|an) ", "", key).replace("'s", "")
    for word, canon in _SYNONYMS.items():
        key = re.sub(rf"\b{re.escape(word)}\b", canon, key)
    return key


def match_name(query: str, names: Sequence[str]) -> str:
    """The scene name ``query`` refers to, by whole words.

    Exact match first; then the most specific name whose words all appear in the query
    ("handle of the top drawer" → "top drawer handle"); then the shortest name holding every
    word of the query ("blue" → "blue block" when there is no "blue line").

    Raises:
        UnknownObjectError: no (or no unique) match; the message lists the scene's names.
    """
    key = normalize_name(query)
    canon = {normalize_name(n): n for n in names}
    if key in canon:
        return canon[key]
    words = set(key.split())
    inside = [(len(c.split()), n) for c, n in canon.items() if set(c.split()) <= words]
    if inside:
        inside.sort(reverse=True)
        if len(inside) == 1 or inside[0][0] > inside[1][0]:
            return inside[0][1]
    holding = sorted((len(c.split()), n) for c, n in canon.items() if words <= set(c.split()))
    if len(holding) == 1 or (len(holding) > 1 and holding[0][0] < holding[1][0]):
        return holding[0][1]
    raise UnknownObjectError(str(query), names)


def leading_name(words: str, names: Sequence[str]) -> str | None:
    """The scene name ``words`` begin with (the longest such name, through the synonym
    table: "blue block to the left" → "blue block"), None when they begin with none."""
    text = normalize_name(words)
    for name in sorted(names, key=len, reverse=True):
        norm = normalize_name(name)
        if text == norm or text.startswith(norm + " "):
            return name
    return None


#: What the entity of interest is called when it is the robot's end effector, after
#: :func:`normalize_name` (which already maps "end effector", "ee", "hand" to "gripper").
END_EFFECTOR_NAMES: Final = frozenset({"gripper", "robot", "end-effector"})


def is_end_effector(name: str) -> bool:
    """Whether an entity name refers to the robot's end effector (through the one synonym
    table)."""
    return normalize_name(name) in END_EFFECTOR_NAMES
