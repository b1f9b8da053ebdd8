"""Fusion: per-camera masks lifted to 3-D, associated across cameras, named, labelled."""

from __future__ import annotations

import dataclasses

import numpy as np

from voxposer.envs import TabletopWorld
from voxposer.perception.detect import detect_in_cloud
from voxposer.perception.observation import Observation
from voxposer.perception.open_vocab.fusion import ViewMask, fuse_masks, labelled_cloud
from voxposer.tabletop import BLOCK_SIZE

from .conftest import BLUE, GREEN


def _masks(obs: Observation, names: tuple[str, ...], query: int = 0) -> list[ViewMask]:
    """Ground-truth masks of ``names`` in every camera, all answering one query."""
    out = []
    for cam, frame in enumerate(obs.cameras):
        for name in names:
            mask = frame.object_ids == obs.label_names.index(name)
            if mask.any():
                out.append(ViewMask(cam, query, mask, 0.5))
    return out


def test_four_cameras_reproduce_the_block_within_a_voxel(scene: Observation,
                                                         world: TabletopWorld) -> None:
    masks = _masks(scene, ("blue block",))
    assert len({m.camera for m in masks}) == 4
    (block,) = fuse_masks(scene.cameras, masks, world.grid, ("block",))
    assert block.name == "block" and len(block.views) == 4
    cloud = labelled_cloud(scene.cameras, (block,), world.grid)
    found = detect_in_cloud(cloud, np.array([0], dtype=np.int32), block.name, world.grid)
    half = BLOCK_SIZE / 2
    known = np.array([[BLUE[0] - half, BLUE[1] - half, 0.0],
                      [BLUE[0] + half, BLUE[1] + half, BLOCK_SIZE]])
    assert np.all(np.abs(found.aabb - known) < world.grid.resolution), found.aabb


def test_two_blocks_of_one_query_are_two_named_objects(scene: Observation,
                                                       world: TabletopWorld) -> None:
    masks = _masks(scene, ("blue block", "green block"))
    found = fuse_masks(scene.cameras, masks, world.grid, ("block",))
    assert sorted(i.name for i in found) == ["block", "block 2"]
    cloud = labelled_cloud(scene.cameras, found, world.grid)
    occupancy = [world.grid.points_to_occupancy(cloud.points[cloud.labels == k])
                 for k in range(2)]
    assert not np.any(occupancy[0] & occupancy[1])
    centres = {i.name: i.centroid[:2] for i in found}
    assert {np.argmin([np.linalg.norm(c - np.array(p[:2])) for p in (BLUE, GREEN)])
            for c in centres.values()} == {0, 1}


def test_names_follow_the_objects_from_a_previous_detection(scene: Observation,
                                                            world: TabletopWorld) -> None:
    blue, green = _masks(scene, ("blue block",)), _masks(scene, ("green block",))
    first = fuse_masks(scene.cameras, blue + green, world.grid, ("block",))
    names = {i.name: i.centroid for i in first}
    assert np.linalg.norm(names["block"][:2] - BLUE[:2]) < 0.02  # the first, equal scores
    # Detected again, the green block now the more confident: by score alone it would be
    # "block"; matched to the previous detection in 3-D, each keeps its name.
    surer = [dataclasses.replace(m, score=0.9) for m in green]
    fresh = fuse_masks(scene.cameras, blue + surer, world.grid, ("block",))
    assert np.linalg.norm({i.name: i.centroid for i in fresh}["block"][:2] - GREEN[:2]) < 0.02
    second = fuse_masks(scene.cameras, blue + surer, world.grid, ("block",), previous=first)
    for inst in second:
        assert np.linalg.norm(inst.centroid - names[inst.name]) < 0.01


def test_masks_outside_the_workspace_are_dropped(scene: Observation,
                                                 world: TabletopWorld) -> None:
    empty = ViewMask(0, 0, np.zeros(scene.cameras[0].depth.shape, dtype=bool), 0.9)
    assert fuse_masks(scene.cameras, [empty], world.grid, ("block",)) == ()
