"""Vague quantities and references by relation: the ``--instructions vague-relational`` split.

A person rarely says "the pink block" and "9cm": they say "the block nearest the robot" and
"a hand's width". This split takes each task's paraphrases (:mod:`voxposer.bench.paraphrases`,
dev phrasings on dev seeds, test phrasings on test seeds) and says its slots as a person would,
while the task's own check still judges the slot's value:

- ``[obj]`` by its relation to the robot (at the back of the table: "you" or "near" would be
  read from the viewer's side), across the table or to another block ("the block nearest the
  robot", "the leftmost block", "the second block from the right", "the block next
  to the green block" within :data:`NEXT_TO_MAX_M`), read from the episode's layout after
  reset: only a relation the named block alone satisfies, by at least
  :data:`RELATION_MARGIN_M` over every other block, is used (none: the colour name stays, and
  :func:`render` says so);
- ``[dist]`` as a vague or other-unit quantity whose plain reading is at least the checked
  distance ("a hand's width" for 9 cm, "roughly two inches" for 5 cm);
- ``[velocity]`` by manner ("a brisk pace", "a crawl") within the check's speed band;
- ``[deixis]`` by the drawer's state ("the open drawer": only the named drawer starts open);
- ``[region]`` by its relation to the robot ("the side of the table nearest the robot": a
  side, the band the check judges, not a half of the table).

Dev and test renderings differ in their words, as the paraphrases do.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any, Final, NamedTuple

import numpy as np

from voxposer.bench.paraphrases import PhrasingSplit, phrasings

#: how much [m] the named block must beat every other block in a relation to be referred to by it.
RELATION_MARGIN_M: Final = 0.05
#: "next to" another block: at most this far [m] between their centres.
NEXT_TO_MAX_M: Final = 0.15
_SLOT = re.compile(r"\[(\w+)\](\s?(?:cm|centimet(?:er|re)s)\b)?")
Words = Mapping[str, tuple[str, ...]]

#: distance [cm, as the attribute says it] → split → vague renderings, each read as at least it.
DISTANCES: Final[dict[str, Words]] = {
    "3": {"dev": ("a few centimetres",), "test": ("three or so centimeters",)},
    "4": {"dev": ("a finger's length or so, say 4 cm",), "test": ("an inch and a half",)},
    "5": {"dev": ("about five centimetres",), "test": ("roughly two inches",)},
    "6": {"dev": ("a little over five centimetres",), "test": ("two and a half inches",)},
    "7": {"dev": ("about a palm's width",), "test": ("roughly three inches",)},
    "8": {"dev": ("a good eight centimetres",), "test": ("a palm's width and a bit",)},
    "9": {"dev": ("a hand's width",), "test": ("about four inches",)},
    "10": {"dev": ("a hand's width or a little more",), "test": ("four inches",)},
    "11": {"dev": ("a little over ten centimetres",), "test": ("four and a half inches",)},
}
#: velocity attribute → split → renderings (noun phrases: "at", "use" and "your speed is"
#: take them) within the check's speed band (bench.config).
VELOCITIES: Final[dict[str, Words]] = {
    "faster speed": {"dev": ("a brisk pace", "a quick pace"),
                     "test": ("the fastest pace that is safe", "a hurried pace")},
    "a quarter of the speed": {"dev": ("a crawl", "a very slow pace"),
                               "test": ("a snail's pace", "a small fraction of your usual speed")},
    "slower speed": {"dev": ("a gentle pace",), "test": ("a somewhat slower pace than usual",)},
    "3x speed": {"dev": ("three times the usual speed",), "test": ("triple speed",)},
}
#: drawer deixis → split → renderings by its state (the task opens only that drawer).
DRAWERS: Final[Words] = {"dev": ("open",), "test": ("opened", "partly open")}
#: region → split → renderings by its relation to the robot (at the back of the table).
REGIONS: Final[dict[str, Words]] = {
    "back side of the table": {"dev": ("side of the table nearest the robot",),
                               "test": ("side of the table next to the robot",)},
    "front side of the table": {"dev": ("side of the table farthest from the robot",),
                                "test": ("side of the table away from the robot",)},
}


#: relations to the robot, as (words, sign): the block whose distance to the robot times the
#: sign is highest is meant. "The robot" is its base, its hand at reset and the arm between them: a
#: block is referred to so only when it is singled out from each.
TO_ROBOT: Final[tuple[tuple[Words, float], ...]] = (
    ({"dev": ("the block nearest the robot",), "test": ("the block closest to the robot",)},
     -1.0),
    ({"dev": ("the block farthest from the robot",),
      "test": ("the block furthest from the robot",)}, 1.0),
)
#: relations across the table, as (words, sign on y): "left" is −y.
ACROSS: Final[tuple[tuple[Words, float], ...]] = (
    ({"dev": ("the leftmost block",), "test": ("the block farthest to the left",)}, -1.0),
    ({"dev": ("the rightmost block",), "test": ("the block farthest to the right",)}, 1.0),
)
#: the relation to another block: "{other}" is its name.
NEXT_TO: Final[Words] = {"dev": ("the block next to the {other}",),
                         "test": ("the block closest to the {other}",)}


def _pick(options: tuple[str, ...], rng: np.random.Generator) -> str:
    return options[int(rng.integers(len(options)))]


def _singled_out(score: np.ndarray, i: int) -> bool:
    """Whether entry ``i`` of ``score`` beats every other by :data:`RELATION_MARGIN_M`."""
    others = np.delete(score, i)
    return others.size > 0 and float(score[i] - others.max()) >= RELATION_MARGIN_M


#: an ordinal position across the table: "{nth}" is "second" or "third", "{side}" the end
#: counted from.
ORDINAL: Final[Words] = {"dev": ("the {nth} block from the {side}",),
                         "test": ("the {nth} block counting from the {side}",)}


def _ordinals(y: np.ndarray, i: int, split: PhrasingSplit, rng: np.random.Generator
              ) -> list[str]:
    """"The second block from the left": block ``i`` second or third from an end of the
    table across it (``y`` [m] of every block, left is −y), at least
    :data:`RELATION_MARGIN_M` from its neighbours in that order."""
    order = np.argsort(y)
    k = int(np.flatnonzero(order == i)[0])
    sorted_y = y[order]
    gaps = np.diff(sorted_y)
    if (k > 0 and gaps[k - 1] < RELATION_MARGIN_M) or (k < len(y) - 1 and gaps[k] < RELATION_MARGIN_M):
        return []
    out = []
    for rank, side in ((k, "left"), (len(y) - 1 - k, "right")):
        if rank in (1, 2):
            out.append(_pick(ORDINAL[split], rng).format(nth=("second", "third")[rank - 1],
                                                           side=side))
    return out


def block_reference(name: str, blocks: Mapping[str, np.ndarray], split: PhrasingSplit,
                    rng: np.random.Generator, robot: tuple[np.ndarray, ...],
                    avoid: tuple[str, ...] = ()) -> str | None:
    """Words that single ``name`` out among ``blocks`` (name → centre [m], x and y used) by a
    relation no other block comes within :data:`RELATION_MARGIN_M` of, picked with ``rng``;
    None when no relation does. ``robot``: the robot's points [m] (its base and its hand);
    ``avoid``: blocks the instruction names otherwise (never the other block of "next to")."""
    names = list(blocks)
    if name not in blocks or len(names) < 2:
        return None
    xy = np.stack([np.asarray(blocks[n], dtype=np.float64)[:2] for n in names])
    i = names.index(name)
    found: list[str] = []
    for words, sign in TO_ROBOT:
        if all(_singled_out(sign * np.linalg.norm(xy - np.asarray(p)[:2], axis=1), i)
               for p in robot):
            found.append(_pick(words[split], rng))
    for words, sign in ACROSS:
        if _singled_out(sign * xy[:, 1], i):
            found.append(_pick(words[split], rng))
    found += _ordinals(xy[:, 1], i, split, rng)
    for j, other in enumerate(names):
        if j != i and other not in avoid:
            near = -np.linalg.norm(xy - xy[j], axis=1)
            if -near[i] <= NEXT_TO_MAX_M and _singled_out(np.delete(near, j), i if i < j else i - 1):
                found.append(_pick(NEXT_TO[split], rng).format(other=other))
    return _pick(tuple(found), rng) if found else None


class Rendered(NamedTuple):
    """An instruction of the split, and the slots it says by relation or vaguely."""

    instruction: str
    vague_slots: tuple[str, ...]


def render(task: str, attrs: Mapping[str, str], blocks: Mapping[str, np.ndarray],
           robot: tuple[np.ndarray, ...], split: PhrasingSplit, seed: int) -> Rendered:
    """The instruction of an episode of ``task``: paraphrase ``seed mod 6`` of ``split``
    with every slot this module can say otherwise said so (module docs); ``blocks``: the
    scene's blocks after reset (name → centre [m]); ``robot``: its base and hand [m]. Deterministic in its arguments."""
    options = phrasings(task, split)
    rng = np.random.default_rng([seed, sum(map(ord, task))])
    changed: list[str] = []

    def slot(m: re.Match[str]) -> str:
        key, value, unit = m.group(1), attrs[m.group(1)], m.group(2) or ""
        said: str | None = None
        if key == "obj":
            said = block_reference(value, blocks, split, rng, robot,
                                   avoid=tuple(attrs[k] for k in ("obstacle",) if k in attrs))
        elif key == "dist" and value in DISTANCES:
            said, unit = _pick(DISTANCES[value][split], rng), ""  # the words carry the unit
        elif key == "velocity" and value in VELOCITIES:
            said = _pick(VELOCITIES[value][split], rng)
        elif key == "deixis":
            said = _pick(DRAWERS[split], rng)
        elif key == "region" and value in REGIONS:
            said = _pick(REGIONS[value][split], rng)
        if said is None:
            return value + unit
        changed.append(key)
        return said + unit

    text = _SLOT.sub(slot, options[seed % len(options)])
    text = re.sub(r"\bthe (the|a|an) ", r"\1 ", text)  # "the [obj]" → "the the block …"
    return Rendered(" ".join(text.split()), tuple(changed))


def scene_blocks(world: Any) -> tuple[dict[str, np.ndarray], tuple[np.ndarray, ...]]:
    """The blocks of ``world`` (name → centre [m], shape (3,)) as reset placed them, and the
    robot's points [m]: its base, its hand and their midpoint (where the arm's perceived
    centre lies)."""
    blocks = {n: np.asarray(world.object_position(n), dtype=np.float64)
              for n in world.object_names if n.endswith(" block")}
    base = np.asarray(world.base_position, dtype=np.float64)
    hand = np.asarray(world.get_ee_pose()[0], dtype=np.float64)
    return blocks, (base, hand, (base + hand) / 2.0)  # the arm's body lies between them


__all__ = ["ACROSS", "DISTANCES", "DRAWERS", "NEXT_TO", "ORDINAL", "REGIONS", "RELATION_MARGIN_M", "TO_ROBOT",
           "VELOCITIES",
           "Rendered", "block_reference", "render", "scene_blocks"]
