"""Obstacles for the planner: the voxels the scene occupies, from a labelled point cloud."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer import catalog
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.names import is_end_effector
from voxposer.perception.point_cloud import PointCloud

#: Points this close to the closed hand belong to what it holds [m].
_HOLD_RADIUS_M = 0.05


def moves_with(entity: str) -> tuple[str, ...]:
    """Catalog names whose points move with ``entity`` and so are no obstacle to its path: the
    entity and its parts, and for a handle also its drawer and the drawer's parts (the drawer
    slides with it; the cabinet around it does not). Unknown names move only with themselves."""
    try:
        obj = catalog.object_named(entity)
    except KeyError:
        return (entity,)
    root = obj.parent if obj.kind == "handle" and obj.parent is not None else obj.name
    return catalog.family(root)


def _kind(name: str) -> str | None:
    """The catalog kind of ``name``, or None for a name the catalog does not hold."""
    try:
        return catalog.object_named(name).kind
    except KeyError:
        return None


def _never_obstacles(names: tuple[str, ...], entity: str, ignore_table: bool) -> NDArray[np.bool_]:
    """Per label (plus a last slot for "no object"): whether its points are left out."""
    skip = np.zeros(len(names) + 1, dtype=bool)
    own = set() if is_end_effector(entity) else set(moves_with(entity))
    for k, label in enumerate(names):
        kind = _kind(label)
        skip[k] = (kind in catalog.ROBOT_KINDS or kind in catalog.FLAT_KINDS or label in own
                   or (ignore_table and label == "table"))
    return skip


def scene_occupancy(
    cloud: PointCloud, label_names: tuple[str, ...], ee_position: ArrayLike, grid: VoxelGrid, *,
    entity: str, holding: bool, ignore_table: bool = False,
) -> NDArray[np.bool_]:
    """Voxels occupied by the scene, shape ``grid.shape``, from ``cloud``.

    Left out: the robot and its gripper; the lines (flat, not interactable); whatever moves with
    the entity (:func:`moves_with`); when ``holding``, any object within 5 cm of the end
    effector (it moves with the hand); and the table when ``ignore_table`` (a pushed object
    slides on it).

    Args:
        cloud: fused cloud with per-point labels (indices into ``label_names``, -1 none).
        label_names: the catalog name of each label.
        ee_position: end-effector position [m], shape (3,).
        grid: the workspace grid.
        entity: the entity's name (ignored if it is the end effector).
        holding: the gripper is closed, possibly on an object.
        ignore_table: drop table points.
    """
    skip = _never_obstacles(tuple(label_names), entity, ignore_table)
    none = len(label_names)
    labels = np.where(cloud.labels < 0, none, cloud.labels)
    keep = ~skip[labels]
    if holding:
        near = np.linalg.norm(cloud.points - np.asarray(ee_position), axis=1) < _HOLD_RADIUS_M
        held = np.unique(labels[near & keep])
        held = held[(held < none)]
        held = held[[label_names[h] != "table" for h in held]] if len(held) else held
        keep &= ~np.isin(labels, held)
    return grid.points_to_occupancy(cloud.points[keep])
