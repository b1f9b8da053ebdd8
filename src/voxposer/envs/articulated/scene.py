"""The articulated tasks' registry and their scenes: table, Panda, one object, four cameras.

``make_object(task, config)`` returns the task's :class:`ArticulatedObject` (unknown names raise
listing the known ones); :func:`build_scene` compiles its scene. Every body, geom, joint, site,
camera and light is named: the table and the Panda as on the tabletop (``table``, ``panda_*``),
the object as its module describes (:mod:`~voxposer.envs.articulated.door`, ``window``,
``fridge``). Segmentation labels are indices into :func:`label_names`: the object's parts, then
"table", "robot" and "gripper".
"""

from __future__ import annotations

from typing import Final

import mujoco
import numpy as np
from numpy.typing import NDArray

from voxposer.catalog import NO_OBJECT
from voxposer.envs.articulated.articulated_object import ArticulatedObject, body_name
from voxposer.envs.articulated.config import ArticulatedConfig
from voxposer.envs.articulated.door import Door
from voxposer.envs.articulated.fridge import Fridge
from voxposer.envs.articulated.parts import add_cameras_and_lights, add_table, new_spec
from voxposer.envs.articulated.window import Window
from voxposer.envs.robot_model import BASE_BODY, PREFIX, add_panda
from voxposer.errors import ConfigError

#: task name → object class, in the paper's Table 3 order.
TASKS: Final[dict[str, type[ArticulatedObject]]] = {
    cls.task: cls for cls in (Door, Window, Fridge)
}
#: Labels after the object's parts, with the body at the root of each.
_SCENE_LABELS: Final = (("table", "table"), ("robot", BASE_BODY),
                        ("gripper", f"{PREFIX}hand_right_gripper"))


def make_object(task: str, config: ArticulatedConfig) -> ArticulatedObject:
    """The object of ``task`` ("door", "window" or "fridge").

    Raises:
        ConfigError: an unknown task, listing the known ones.
    """
    if task not in TASKS:
        raise ConfigError(f"unknown articulated task {task!r}; tasks are: {', '.join(TASKS)}")
    return TASKS[task](config)


def label_names(obj: ArticulatedObject) -> tuple[str, ...]:
    """Segmentation label names: the object's parts, then "table", "robot", "gripper"."""
    return obj.parts + tuple(name for name, _ in _SCENE_LABELS)


def build_scene(config: ArticulatedConfig, obj: ArticulatedObject) -> mujoco.MjModel:
    """The compiled scene of ``obj``: its base is a mocap body at its nominal place."""
    spec = new_spec(f"voxposer_{obj.task}", config.timestep, config.cameras)
    add_table(spec, config.table_min, config.table_max)
    add_panda(spec, config.robot_base)
    x, y = obj.nominal_xy
    base = spec.worldbody.add_body(name=obj.base_body, mocap=True, pos=[x, y, 0.0])
    obj.build(spec, base)
    add_cameras_and_lights(spec, config.cameras)
    return spec.compile()


def geom_labels(model: mujoco.MjModel, obj: ArticulatedObject) -> NDArray[np.int32]:
    """Label (index into :func:`label_names`, or ``NO_OBJECT``) of every geom, shape (ngeom,):
    the label of its body's nearest ancestor that is a part's (or the table's, the robot's,
    the gripper's) root body."""
    roots = {body_name(part): k for k, part in enumerate(obj.parts)}
    roots |= {body: len(obj.parts) + k for k, (_, body) in enumerate(_SCENE_LABELS)}
    body_label = np.full(model.nbody, NO_OBJECT, dtype=np.int32)
    for b in range(model.nbody):
        walk = b
        while walk > 0 and model.body(walk).name not in roots:
            walk = int(model.body_parentid[walk])
        if walk > 0:
            body_label[b] = roots[model.body(walk).name]
    labels = body_label[model.geom_bodyid]
    for geom, part in obj.relabel.items():
        labels[model.geom(geom).id] = obj.parts.index(part)
    return labels


__all__ = ["TASKS", "build_scene", "geom_labels", "label_names", "make_object"]
