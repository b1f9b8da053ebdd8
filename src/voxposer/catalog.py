"""What the tabletop holds, described once: every nameable object, its kind, parts and colour.

A base module (like :mod:`voxposer.errors` and :mod:`voxposer.places`): the simulator builds its
scene and its segmentation labels from it, perception resolves names and object families with it,
the programs' test scene lays out the same objects. It imports no stage.

Segmentation labels are indices into :data:`OBJECTS`: label ``k`` is ``OBJECTS[k]``, and
:data:`NO_OBJECT` marks pixels and points of no object. Parts nest: "top drawer handle" ⊂
"top drawer" ⊂ "cabinet"; "gripper" ⊂ "robot".
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import Final, Literal

from voxposer.errors import UnknownObjectError

#: The paper's ten colours (App. A.5), in label order.
COLOR_NAMES: Final = ("blue", "green", "yellow", "pink", "brown", "red", "orange", "purple",
                      "cyan", "gray")
#: The three drawers, top to bottom.
DRAWERS: Final = ("top", "middle", "bottom")
#: Label of pixels/points that belong to no object (floor, background).
NO_OBJECT: Final = -1

Kind = Literal["table", "robot", "gripper", "block", "line", "cabinet", "drawer", "handle"]
#: Kinds of parts that slide along one axis (a drawer and its handle) rather than move freely.
SLIDING_KINDS: Final = frozenset({"drawer", "handle"})
#: Kinds that are the robot itself: never obstacles of its own paths.
ROBOT_KINDS: Final = frozenset({"robot", "gripper"})
#: Kinds that are flat marks on the table (lines): landmarks, not obstacles (paper App. A.5).
FLAT_KINDS: Final = frozenset({"line"})


@dataclass(frozen=True)
class SceneObject:
    """A nameable object of the scene.

    Attributes:
        name: the canonical language name ("blue block").
        kind: what it is (see :data:`Kind`).
        parent: the canonical name of the object this is a part of, or None.
        colour: one of :data:`COLOR_NAMES` for blocks and lines.
    """

    name: str
    kind: Kind
    parent: str | None = None
    colour: str | None = None


def _objects() -> tuple[SceneObject, ...]:
    objs = [
        SceneObject("table", "table"),
        SceneObject("robot", "robot"),
        SceneObject("gripper", "gripper", parent="robot"),
        SceneObject("cabinet", "cabinet"),
    ]
    for which in DRAWERS:
        objs.append(SceneObject(f"{which} drawer", "drawer", parent="cabinet"))
        objs.append(SceneObject(f"{which} drawer handle", "handle", parent=f"{which} drawer"))
    objs += [SceneObject(f"{c} block", "block", colour=c) for c in COLOR_NAMES]
    objs += [SceneObject(f"{c} line", "line", colour=c) for c in COLOR_NAMES]
    return tuple(objs)


#: Every nameable object, in label order.
OBJECTS: Final = _objects()
_INDEX: Final = {obj.name: k for k, obj in enumerate(OBJECTS)}


def object_named(name: str) -> SceneObject:
    """The object with canonical name ``name`` (exact; perception resolves free-form names).

    Raises:
        UnknownObjectError: listing every known name.
    """
    if name not in _INDEX:
        raise UnknownObjectError(str(name), _INDEX)
    return OBJECTS[_INDEX[name]]


def label_of(name: str) -> int:
    """Segmentation label of the object with canonical name ``name``."""
    object_named(name)
    return _INDEX[name]


@cache
def lineage(name: str) -> tuple[str, ...]:
    """The object and the objects it is a part of, innermost first ("top drawer handle",
    "top drawer", "cabinet")."""
    chain = [object_named(name)]
    while chain[-1].parent is not None:
        chain.append(object_named(chain[-1].parent))
    return tuple(o.name for o in chain)


@cache
def family(name: str) -> tuple[str, ...]:
    """The object and all of its parts, at any depth ("top drawer" → the drawer and its
    handle)."""
    object_named(name)
    return tuple(o.name for o in OBJECTS if name in lineage(o.name))


__all__ = ["COLOR_NAMES", "DRAWERS", "FLAT_KINDS", "NO_OBJECT", "OBJECTS", "ROBOT_KINDS",
           "SLIDING_KINDS", "Kind", "SceneObject", "family", "label_of", "lineage",
           "object_named"]
