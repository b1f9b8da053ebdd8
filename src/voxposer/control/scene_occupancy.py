"""Obstacles for the planner from an observation's labelled point cloud."""

from __future__ import annotations

import re
from typing import Any

import numpy as np
from numpy.typing import NDArray

from voxposer.valuemaps.grid import VoxelGrid

#: Names that mean the robot's end effector when used as the entity of interest.
END_EFFECTOR_NAMES = frozenset({"gripper", "end effector", "ee", "hand", "robot", "end-effector"})
_ROBOT_WORDS = ("robot", "gripper")
_HOLD_RADIUS_M = 0.05


def is_end_effector(name: str) -> bool:
    """Whether an entity name refers to the robot's end effector."""
    key = re.sub(r"\s+", " ", name.strip().lower()).removeprefix("the ")
    return key in END_EFFECTOR_NAMES


def _family(label_name: str, entity: str) -> bool:
    """Whether ``label_name`` is the entity or one of its parts / its parent object."""
    return (
        label_name == entity
        or label_name.startswith(entity + " ")
        or entity.startswith(label_name + " ")
    )


def scene_occupancy(
    obs: Any, grid: VoxelGrid, *, entity: str, holding: bool, ignore_table: bool = False
) -> NDArray[np.bool_]:
    """Voxels occupied by the scene, shape ``grid.shape``, from ``obs.cloud``.

    Left out: the robot and its gripper; the lines (flat, not interactable); the entity itself (and its parts or parent, e.g. a
    drawer and its handle); when ``holding``, any object within 5 cm of the end effector (it
    moves with the hand); and the table when ``ignore_table`` (a pushed object slides on it).

    Args:
        obs: an observation with ``cloud`` (points, labels), ``label_names`` and ``ee_position``.
        grid: the workspace grid.
        entity: the entity's name (ignored if it is the end effector).
        holding: the gripper is closed, possibly on an object.
        ignore_table: drop table points.
    """
    cloud = obs.cloud
    names = list(obs.label_names)
    skip = np.zeros(len(names) + 1, dtype=bool)  # last slot: label -1 (unlabelled)
    ent = "" if is_end_effector(entity) else entity
    for k, label in enumerate(names):
        if any(w in label for w in _ROBOT_WORDS) or (ent and _family(label, ent)):
            skip[k] = True
        if ignore_table and label == "table":
            skip[k] = True
        if label.endswith(" line"):  # flat visual landmarks, not obstacles (paper App. A.5)
            skip[k] = True
    labels = np.where(cloud.labels < 0, len(names), cloud.labels)
    keep = ~skip[labels]
    if holding:
        near = np.linalg.norm(cloud.points - np.asarray(obs.ee_position), axis=1) < _HOLD_RADIUS_M
        held = np.unique(labels[near & keep])
        held = held[(held < len(names))]
        held = held[[names[h] != "table" for h in held]] if len(held) else held
        keep &= ~np.isin(labels, held)
    return grid.points_to_occupancy(cloud.points[keep])
