"""The one place where language names ("blue block", "top drawer handle") meet scene elements.

Every nameable object is a :class:`SceneObject` with the MuJoCo body at its root and, for parts,
the object it belongs to ("top drawer handle" ⊂ "top drawer" ⊂ "cabinet"; "gripper" ⊂ "robot").
Each geom of the model carries the label (index into :data:`OBJECTS`) of the most specific object
it belongs to; asking for an object gathers the labels of the object and all its parts.

Names are matched leniently: case-insensitive, surrounding spaces and a leading "the" ignored,
underscores read as spaces, and a few synonyms (:data:`ALIASES`) accepted.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Final

import mujoco
import numpy as np
from numpy.typing import NDArray

from voxposer.envs.config import COLORS, DRAWERS
from voxposer.envs.robot_model import BASE_BODY, PREFIX
from voxposer.errors import UnknownObjectError

#: Label of pixels/points/geoms that belong to no object (floor, background).
NO_OBJECT: Final = -1


@dataclass(frozen=True)
class SceneObject:
    """A nameable object of the scene.

    Attributes:
        name: the language name ("blue block").
        kind: "table", "robot", "gripper", "block", "line", "cabinet", "drawer" or "handle".
        body: the MuJoCo body at the object's root.
        parent: the language name of the object this is a part of, or None.
        colour: one of :data:`~voxposer.envs.config.COLORS` for blocks and lines.
    """

    name: str
    kind: str
    body: str
    parent: str | None = None
    colour: str | None = None


def _objects() -> tuple[SceneObject, ...]:
    objs = [
        SceneObject("table", "table", "table"),
        SceneObject("robot", "robot", BASE_BODY),
        SceneObject("gripper", "gripper", f"{PREFIX}hand_right_gripper", parent="robot"),
        SceneObject("cabinet", "cabinet", "cabinet"),
    ]
    for which in DRAWERS:
        objs.append(SceneObject(f"{which} drawer", "drawer", f"{which}_drawer", parent="cabinet"))
        objs.append(SceneObject(f"{which} drawer handle", "handle", f"{which}_drawer_handle",
                                parent=f"{which} drawer"))
    for colour in COLORS:
        objs.append(SceneObject(f"{colour} block", "block", f"{colour}_block", colour=colour))
    for colour in COLORS:
        objs.append(SceneObject(f"{colour} line", "line", f"{colour}_line", colour=colour))
    return tuple(objs)


#: Every nameable object, in label order.
OBJECTS: Final = _objects()
#: Synonyms → canonical names (after normalisation).
ALIASES: Final[dict[str, str]] = {
    "topmost drawer": "top drawer",
    "bottommost drawer": "bottom drawer",
    "second to the top drawer": "middle drawer",
    "second to the bottom drawer": "middle drawer",
    "topmost drawer handle": "top drawer handle",
    "bottommost drawer handle": "bottom drawer handle",
    "top handle": "top drawer handle",
    "middle handle": "middle drawer handle",
    "bottom handle": "bottom drawer handle",
    "end effector": "gripper",
    "ee": "gripper",
    "hand": "gripper",
    "drawer cabinet": "cabinet",
    **{f"grey {kind}": f"gray {kind}" for kind in ("block", "line")},
    **{f"{c} cube": f"{c} block" for c in COLORS},
}


def normalize_name(name: str) -> str:
    """Canonical form of an object name: lower case, single spaces, no leading "the"."""
    key = re.sub(r"[\s_]+", " ", str(name)).strip().lower()
    key = re.sub(r"^the ", "", key)
    key = key.replace("'s", "")
    return ALIASES.get(key, key)


class ObjectRegistry:
    """Maps names to objects and geoms of a compiled scene to object labels.

    Attributes:
        geom_labels: label (index into :data:`OBJECTS`, or :data:`NO_OBJECT`) of every geom,
            shape (ngeom,).
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        self._index = {obj.name: k for k, obj in enumerate(OBJECTS)}
        body_label = np.full(model.nbody, NO_OBJECT, dtype=np.int32)
        root_of = {obj.body: k for k, obj in enumerate(OBJECTS)}
        for b in range(model.nbody):
            walk = b
            while walk > 0 and model.body(walk).name not in root_of:
                walk = int(model.body_parentid[walk])
            if walk > 0:
                body_label[b] = root_of[model.body(walk).name]
        self.geom_labels: NDArray[np.int32] = body_label[model.geom_bodyid]
        self.body_labels: NDArray[np.int32] = body_label
        self._family: dict[str, NDArray[np.int32]] = {}
        for obj in OBJECTS:
            members = [k for k, o in enumerate(OBJECTS) if self._is_within(o.name, obj.name)]
            self._family[obj.name] = np.asarray(members, dtype=np.int32)

    @staticmethod
    def _is_within(name: str, ancestor: str) -> bool:
        parents = {o.name: o.parent for o in OBJECTS}
        walk: str | None = name
        while walk is not None:
            if walk == ancestor:
                return True
            walk = parents[walk]
        return False

    @property
    def names(self) -> tuple[str, ...]:
        """Every object name the registry knows (present in the scene or not)."""
        return tuple(self._index)

    def resolve(self, name: str, available: tuple[str, ...] | None = None) -> SceneObject:
        """The object called ``name`` (lenient matching).

        Args:
            name: a language name such as "the Blue Block" or "top drawer handle".
            available: names currently in the scene; defaults to every known object.

        Raises:
            UnknownObjectError: listing ``available`` when the name matches none of them.
        """
        known = self.names if available is None else available
        key = normalize_name(name)
        if key not in self._index or key not in known:
            raise UnknownObjectError(str(name), known)
        return OBJECTS[self._index[key]]

    def label(self, name: str) -> int:
        """Label of the object called ``name`` (exact canonical name)."""
        return self._index[normalize_name(name)]

    def family_labels(self, name: str) -> NDArray[np.int32]:
        """Labels of the object and all of its parts, shape (k,)."""
        return self._family[normalize_name(name)]
