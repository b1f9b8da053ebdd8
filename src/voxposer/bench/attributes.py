"""The randomisable attributes of the 13 simulated tasks (paper App. A.5), seen and unseen.

"Seen" attributes may appear in prompts; "unseen" ones are held out. The lists are exactly the
paper's; ``obstacle`` reuses the block list (the paper names no separate list for it).
"""

from __future__ import annotations

from typing import Final, Literal

from voxposer.errors import ConfigError

Split = Literal["seen", "unseen"]
SPLITS: Final[tuple[Split, ...]] = ("seen", "unseen")

#: attribute slot → split → values (App. A.5, verbatim).
ATTRIBUTES: Final[dict[str, dict[str, tuple[str, ...]]]] = {
    "pos": {
        "seen": ("back left corner of the table", "front right corner of the table",
                 "right side of the table", "back side of the table"),
        "unseen": ("back right corner of the table", "front left corner of the table",
                   "left side of the table", "front side of the table"),
    },
    "obj": {
        "seen": ("blue block", "green block", "yellow block", "pink block", "brown block"),
        "unseen": ("red block", "orange block", "purple block", "cyan block", "gray block"),
    },
    "preposition": {
        "seen": ("left of", "front side of", "top of"),
        "unseen": ("right of", "back side of"),
    },
    "deixis": {
        "seen": ("topmost", "second to the bottom"),
        "unseen": ("bottommost", "second to the top"),
    },
    "dist": {"seen": ("3", "5", "7", "9", "11"), "unseen": ("4", "6", "8", "10")},
    "region": {
        "seen": ("right side of the table", "back side of the table"),
        "unseen": ("left side of the table", "front side of the table"),
    },
    "velocity": {
        "seen": ("faster speed", "a quarter of the speed"),
        "unseen": ("slower speed", "3x speed"),
    },
    "line": {
        "seen": ("blue line", "green line", "yellow line", "pink line", "brown line"),
        "unseen": ("red line", "orange line", "purple line", "cyan line", "gray line"),
    },
}
ATTRIBUTES["obstacle"] = ATTRIBUTES["obj"]

#: deixis → the drawer it names (top to bottom: top, middle, bottom).
DEIXIS_DRAWER: Final[dict[str, str]] = {
    "topmost": "top", "second to the bottom": "middle", "bottommost": "bottom",
    "second to the top": "middle",
}


def check_split(split: str) -> Split:
    """``split`` if it is "seen" or "unseen"; raises ConfigError listing both otherwise."""
    if split not in SPLITS:
        raise ConfigError(f"unknown split {split!r}; splits are: {', '.join(SPLITS)}")
    return split


def values(slot: str, split: str) -> tuple[str, ...]:
    """The values of attribute ``slot`` in ``split``; raises ConfigError listing known slots."""
    if slot not in ATTRIBUTES:
        raise ConfigError(f"unknown attribute {slot!r}; attributes are: {', '.join(ATTRIBUTES)}")
    return ATTRIBUTES[slot][check_split(split)]
