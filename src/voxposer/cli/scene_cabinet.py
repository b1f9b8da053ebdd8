"""Whether ``voxposer run``'s scene has the cabinet: not when it would cover a named place.

The cabinet stands on the right of the table, over the "right side" and "front right corner"
places. An instruction that names such a place (and no cabinet, drawer or handle) gets a scene
without the cabinet, so its target is reachable; every other scene keeps it.
"""

from __future__ import annotations

import re
from typing import Final

from voxposer import tabletop
from voxposer.places import PLACES

#: how far [m] around the cabinet's footprint a place counts as covered (the hand's size).
COVER_MARGIN_M: Final = 0.05
KEPT: Final = "stands on the table"
_CABINET_WORDS: Final = re.compile(r"\b(cabinet|cupboard|drawers?|handles?)\b")


def covered_places() -> tuple[str, ...]:
    """The table places (their words, "right side") whose point lies under the cabinet."""
    (cx, cy), (sx, sy, _) = tabletop.CABINET_POSITION, tabletop.CABINET_SIZE
    out = []
    for place in PLACES.values():
        x, y = place.point
        if abs(x - cx) <= sx / 2 + COVER_MARGIN_M and abs(y - cy) <= sy / 2 + COVER_MARGIN_M:
            out.append(place.words)
    return tuple(out)


def cabinet_choice(instruction: str) -> tuple[bool, str]:
    """(whether the scene has the cabinet, why), from the instruction's words."""
    text = " ".join(instruction.lower().split())
    if _CABINET_WORDS.search(text):
        return True, "named in the instruction"
    for words in covered_places():
        if re.search(rf"\b{re.escape(words)}\b", text):
            return False, (f"left out: the {words} of the table, which the instruction names, "
                           "lies under it")
    return True, KEPT
