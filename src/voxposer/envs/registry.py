"""The simulator's side of the object catalog: MuJoCo bodies and geom labels of each object.

The objects themselves (names, kinds, parts) are described once in :mod:`voxposer.catalog`;
here each gets the MuJoCo body at its root, and every geom of the compiled model the label
(index into :data:`voxposer.catalog.OBJECTS`) of the most specific object it belongs to, so the
renderer can write a ground-truth segmentation channel. Names here are canonical catalog names;
free-form names ("the topmost drawer") are perception's business.
"""

from __future__ import annotations

import mujoco
import numpy as np
from numpy.typing import NDArray

from voxposer.catalog import NO_OBJECT, OBJECTS, SceneObject, object_named
from voxposer.envs.robot_model import BASE_BODY, PREFIX
from voxposer.errors import UnknownObjectError

#: MuJoCo root body of objects whose body is not their name with underscores.
_BODIES = {"robot": BASE_BODY, "gripper": f"{PREFIX}hand_right_gripper"}


def body_of(obj: SceneObject) -> str:
    """The MuJoCo body at the root of ``obj`` ("blue block" → ``blue_block``)."""
    return _BODIES.get(obj.name, obj.name.replace(" ", "_"))


class ObjectRegistry:
    """Maps catalog objects to bodies, and geoms of a compiled scene to object labels.

    Attributes:
        geom_labels: label (index into :data:`OBJECTS`, or :data:`NO_OBJECT`) of every geom,
            shape (ngeom,).
        body_labels: the same for every body, shape (nbody,).
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        body_label = np.full(model.nbody, NO_OBJECT, dtype=np.int32)
        root_of = {body_of(obj): k for k, obj in enumerate(OBJECTS)}
        for b in range(model.nbody):
            walk = b
            while walk > 0 and model.body(walk).name not in root_of:
                walk = int(model.body_parentid[walk])
            if walk > 0:
                body_label[b] = root_of[model.body(walk).name]
        self.geom_labels: NDArray[np.int32] = body_label[model.geom_bodyid]
        self.body_labels: NDArray[np.int32] = body_label

    @staticmethod
    def resolve(name: str, available: tuple[str, ...] | None = None) -> SceneObject:
        """The catalog object with canonical name ``name``.

        Args:
            name: a canonical name such as "blue block" or "top drawer handle".
            available: names currently in the scene; defaults to every catalog object.

        Raises:
            UnknownObjectError: listing ``available`` when ``name`` is none of them.
        """
        known = tuple(o.name for o in OBJECTS) if available is None else available
        if name not in known:
            raise UnknownObjectError(str(name), known)
        return object_named(name)

    @staticmethod
    def body(name: str) -> str:
        """The MuJoCo body at the root of the object called ``name`` (canonical)."""
        return body_of(object_named(name))
