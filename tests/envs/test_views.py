"""Camera views: cameras streaming at their own rate (``CameraConfig.frame_hz``)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from voxposer.catalog import NO_OBJECT
from voxposer.envs import SceneLayout, TabletopWorld, WorldConfig
from voxposer.envs.config import CameraConfig
from voxposer.errors import ConfigError
from voxposer.perception.point_cloud import fuse_views
from voxposer.perception.segmentation import SegmentationPerceiver


def _world(frame_hz: float | None) -> TabletopWorld:
    cfg = WorldConfig()
    return TabletopWorld(replace(cfg, cameras=replace(cfg.cameras, frame_hz=frame_hz)))


def _advance_s(world: TabletopWorld, seconds: float) -> None:
    world.advance(round(seconds / world.model.opt.timestep))


def test_at_2_5_hz_each_replan_renews_two_of_four_views_and_a_reset_all() -> None:
    world = _world(2.5)
    try:
        world.reset(np.random.default_rng(0), SceneLayout())
        prev = world.observe(rgb=False)
        renewed, age = [], {f.name: 0 for f in prev.cameras}
        for _ in range(6):  # five replans a second, as the executor observes
            _advance_s(world, 0.2)
            obs = world.observe(rgb=False)
            new = [a is not b for a, b in zip(obs.cameras, prev.cameras, strict=True)]
            renewed.append(sum(new))
            for frame, is_new in zip(obs.cameras, new, strict=True):
                age[frame.name] = 0 if is_new else age[frame.name] + 1
                assert age[frame.name] <= 1  # no view is older than one frame period
            # the robot's state is always current
            np.testing.assert_allclose(obs.ee_position, world.get_ee_pose()[0])
            prev = obs
        assert renewed == [2] * 6
        # a colour request is not served by a depth-only frame
        coloured = world.observe(rgb=True)
        assert all(a is not b for a, b in zip(coloured.cameras, prev.cameras, strict=True))
        world.reset(np.random.default_rng(1), SceneLayout())
        after = world.observe(rgb=False)
        assert all(a is not b for a, b in zip(after.cameras, coloured.cameras, strict=True))
    finally:
        world.close()


def test_without_a_rate_every_observation_renders_every_camera(fresh: TabletopWorld) -> None:
    first = fresh.observe(rgb=False)
    _advance_s(fresh, 0.2)
    second = fresh.observe(rgb=False)
    assert all(a is not b for a, b in zip(first.cameras, second.cameras, strict=True))


def test_a_view_kept_is_not_lifted_again_and_the_cloud_is_the_same() -> None:
    """The perceiver reuses the points of a view that was not renewed; the fused cloud equals
    one fused from scratch."""
    world = _world(2.5)
    try:
        world.reset(np.random.default_rng(0), SceneLayout())
        perceiver = SegmentationPerceiver(world, world.grid)
        perceiver.point_cloud()
        before = {i: points for i, (_, points) in perceiver._views.items()}
        _advance_s(world, 0.2)
        reused = perceiver.point_cloud()
        assert all(view is perceiver.observe().cameras[i]
                   for i, (view, _) in perceiver._views.items())
        # the two views not renewed kept their points; the two new ones were lifted
        assert sum(perceiver._views[i][1] is before[i] for i in before) == 2
        scratch = fuse_views(perceiver.observe().cameras, world.grid)
        np.testing.assert_array_equal(reused.points, scratch.points)
        np.testing.assert_array_equal(reused.labels, scratch.labels)
        np.testing.assert_array_equal(reused.camera, scratch.camera)
    finally:
        world.close()


@pytest.mark.parametrize("bad", [0.0, -2.0, float("nan"), float("inf")])
def test_a_bad_frame_rate_is_refused(bad: float) -> None:
    with pytest.raises(ConfigError, match=r"CameraConfig\.frame_hz must be a positive finite"):
        CameraConfig(frame_hz=bad)


def test_pixels_without_labels_are_those_of_both_passes_and_labels_are_rendered_when_asked(
) -> None:
    """``labels=False`` reads the depth with the colour (one pass): the same colour and depth
    as the two passes, no label ids; held frames serve it, not a later labelled ask."""
    worlds = [_world(None), _world(2.5)]
    try:
        for world in worlds:
            world.reset(np.random.default_rng(0), SceneLayout(blocks=("blue", "green")))
        both = worlds[0].observe(rgb=True)
        pixels = worlds[1].observe(labels=False)
        for a, b in zip(both.cameras, pixels.cameras, strict=True):
            np.testing.assert_array_equal(a.rgb, b.rgb)
            np.testing.assert_array_equal(a.depth, b.depth)  # inf where nothing is in range
            assert np.isfinite(a.depth).mean() > 0.5
            assert (b.object_ids == NO_OBJECT).all() and (a.object_ids != NO_OBJECT).any()
        world = worlds[1]
        assert world.observe(rgb=True, labels=False) is pixels
        labelled = world.observe()
        assert all(a is not b for a, b in zip(labelled.cameras, pixels.cameras, strict=True))
        assert all((f.object_ids != NO_OBJECT).any() for f in labelled.cameras)
        assert world.observe(labels=False) is labelled  # holds more than asked
        assert world.observe(rgb=False) is labelled
    finally:
        for world in worlds:
            world.close()
