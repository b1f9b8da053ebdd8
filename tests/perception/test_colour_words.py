"""Colour words: remembered per RGB value, identical to computing them afresh."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from voxposer.envs import SceneLayout, TabletopWorld, WorldConfig
from voxposer.perception import pixel_labels
from voxposer.perception.colour_names import PAINT_RGB, classify_colours, colour_labels
from voxposer.perception.pixel_labels import ViewClouds, colour_cloud
from voxposer.perception.point_cloud import fuse_views


def test_remembered_words_equal_fresh_ones_for_any_colour() -> None:
    rng = np.random.default_rng(0)
    paint = np.round(np.asarray(PAINT_RGB) * 255).astype(int)
    near_paint = np.clip(paint[rng.integers(0, len(paint), 20_000)]
                         + rng.integers(-40, 41, (20_000, 3)), 0, 255)
    pixels = np.concatenate([rng.integers(0, 256, (20_000, 3)), near_paint]).astype(np.uint8)
    fresh = classify_colours(pixels)
    assert len(set(fresh.tolist())) >= 8  # the sample reaches most words (and no word)
    np.testing.assert_array_equal(colour_labels(pixels), fresh)  # first time: classified
    np.testing.assert_array_equal(colour_labels(pixels[::-1]), fresh[::-1])  # then remembered
    image = pixels[:40_000].reshape(200, 200, 3)
    assert colour_labels(image).shape == (200, 200)


def test_the_colour_cloud_carries_each_points_own_colour_word() -> None:
    world = TabletopWorld()
    world.reset(np.random.default_rng(1), SceneLayout(blocks=("blue", "red")))
    obs = world.observe(rgb=True)
    cloud = colour_cloud(obs, world.grid)
    plain = fuse_views(obs.cameras, world.grid)
    np.testing.assert_array_equal(cloud.points, plain.points)
    np.testing.assert_array_equal(cloud.labels, classify_colours(plain.colors))
    assert np.any(cloud.labels == 0) and np.any(cloud.labels == 5)  # blue and red found


def test_a_view_not_renewed_is_not_lifted_again_and_the_cloud_is_unchanged(
        monkeypatch: pytest.MonkeyPatch) -> None:
    cfg = WorldConfig()
    world = TabletopWorld(replace(cfg, cameras=replace(cfg.cameras, frame_hz=2.5)))
    world.reset(np.random.default_rng(1), SceneLayout(blocks=("blue", "red")))
    lifted: list[int] = []
    real = pixel_labels.fuse_views
    monkeypatch.setattr(pixel_labels, "fuse_views",
                        lambda views, grid: lifted.append(len(views)) or real(views, grid))
    kept: ViewClouds = {}
    first = colour_cloud(world.observe(rgb=True), world.grid, kept)
    assert sum(lifted) == 4
    world.advance(round(0.2 / world.model.opt.timestep))  # one 5 Hz replan later
    obs = world.observe(rgb=True)
    renewed = sum(view is not kept[k][0] for k, view in enumerate(obs.cameras))
    assert renewed == 2  # two of the four cameras have a new frame at 2.5 Hz
    again = colour_cloud(obs, world.grid, kept)
    assert sum(lifted) == 4 + 2  # only the two new views lifted
    plain = colour_cloud(obs, world.grid)  # every view afresh
    for field in ("points", "normals", "labels", "colors", "camera"):
        np.testing.assert_array_equal(getattr(again, field), getattr(plain, field))
    assert len(again) != len(first) or not np.array_equal(again.points, first.points)
