"""The colour-depth perceiver finds objects from RGB-D pixels alone, close to the simulator."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from voxposer.envs import COLORS, SceneLayout, TabletopWorld
from voxposer.errors import UnknownObjectError
from voxposer.perception import Perceiver
from voxposer.perception.colour_depth import ColourDepthPerceiver
from voxposer.perception.colour_names import PAINT_RGB
from voxposer.perception.observation import Observation
from voxposer.perception.recorded import RecordedObservations

LAYOUT = SceneLayout(blocks=("blue", "green", "gray"), lines=("yellow",),
                     poses={"blue block": (-0.2, -0.1), "green block": (-0.10, -0.1),
                            "yellow line": (-0.05, 0.1, 0.4)},
                     extra_blocks=(0, 0), extra_lines=(0, 0), drawer_openings={"middle": 0.11})


@pytest.fixture(scope="module")
def scene(world: TabletopWorld) -> Observation:
    """The shared world reset with two blocks 10 cm apart, a gray one, a line and an open
    drawer; its observation with the segmentation channel blanked out (all -1, as a camera
    without one)."""
    world.reset(np.random.default_rng(3), LAYOUT)
    obs = world.observe(rgb=True)
    blank = tuple(dataclasses.replace(f, object_ids=np.full_like(f.object_ids, -1))
                  for f in obs.cameras)
    return dataclasses.replace(obs, cameras=blank, label_names=())


@pytest.fixture(scope="module")
def pixels(scene: Observation, world: TabletopWorld) -> ColourDepthPerceiver:
    return ColourDepthPerceiver(RecordedObservations(scene, object_names=()), world.grid)


def test_it_is_a_perceiver(pixels: ColourDepthPerceiver) -> None:
    assert isinstance(pixels, Perceiver)


def test_paint_table_matches_the_simulators_colours() -> None:
    np.testing.assert_allclose(PAINT_RGB, [rgba[:3] for rgba in COLORS.values()])


def test_blue_block_centre_within_1_5_cm(pixels: ColourDepthPerceiver,
                                         world: TabletopWorld) -> None:
    found = pixels.detect("the blue cube")
    assert np.linalg.norm(found.position - world.object_position("blue block")) < 0.015


def test_two_colours_are_two_objects(pixels: ColourDepthPerceiver,
                                     world: TabletopWorld) -> None:
    blue, green = pixels.detect("blue block"), pixels.detect("green block")
    assert not np.any(blue.occupancy & green.occupancy)
    assert np.linalg.norm(green.position - world.object_position("green block")) < 0.015
    assert np.linalg.norm(blue.position - green.position) > 0.04


def test_gray_block_is_not_the_gray_robot(pixels: ColourDepthPerceiver,
                                          world: TabletopWorld) -> None:
    found = pixels.detect("gray block")
    assert np.all(np.ptp(found.points, axis=0) < 0.08)
    assert np.linalg.norm(found.position - world.object_position("gray block")) < 0.015


def test_line_is_flat(pixels: ColourDepthPerceiver, world: TabletopWorld) -> None:
    line = pixels.detect("yellow line")
    assert line.aabb[1, 2] - line.aabb[0, 2] < 0.01
    assert np.linalg.norm(line.position[:2] - world.object_position("yellow line")[:2]) < 0.02


def test_open_drawer_opening_measured_from_depth(pixels: ColourDepthPerceiver,
                                                 world: TabletopWorld) -> None:
    for which in ("top", "middle", "bottom"):
        assert abs(pixels.drawer_opening(which) - world.drawer_opening(which)) < 0.02
    handle = pixels.detect("middle drawer handle")
    assert np.linalg.norm(handle.position - world.object_position("middle drawer handle")) < 0.02
    axis = pixels.sliding_axis("middle drawer handle")
    assert axis is not None and axis @ world.drawer_axis("middle") > 0.95


def test_absent_object_is_unknown_naming_the_query(pixels: ColourDepthPerceiver) -> None:
    with pytest.raises(UnknownObjectError, match="red block") as err:
        pixels.detect("red block")
    assert "blue block" in str(err.value)
    assert "red block" not in pixels.object_names
    assert {"blue block", "green block", "gray block", "yellow line", "cabinet",
            "middle drawer handle"} <= set(pixels.object_names)


def test_segmentation_channel_is_never_read(scene: Observation, world: TabletopWorld) -> None:
    """With an object-id channel naming every pixel the middle drawer handle, nothing changes."""
    wrong = tuple(dataclasses.replace(f, object_ids=np.full_like(f.object_ids, 7))
                  for f in scene.cameras)
    misled = ColourDepthPerceiver(
        RecordedObservations(dataclasses.replace(scene, cameras=wrong), object_names=()),
        world.grid)
    honest = ColourDepthPerceiver(RecordedObservations(scene, object_names=()), world.grid)
    assert misled.object_names == honest.object_names
    np.testing.assert_array_equal(misled.point_cloud().labels, honest.point_cloud().labels)


def test_noisy_table_points_are_table_not_obstacles(world: TabletopWorld) -> None:
    """With a consumer camera's depth noise and calibration error the table's points scatter
    ~1 cm about its plane; they must stay table, so a pushed block is not walled in by them."""
    from voxposer.catalog import NO_OBJECT
    from voxposer.perception.noisy_source import NoisyObservationSource
    from voxposer.perception.sensor_noise import SensorNoiseConfig

    world.reset(np.random.default_rng(3), LAYOUT)
    config = dataclasses.replace(SensorNoiseConfig(), mask_corruption=False)
    noisy = ColourDepthPerceiver(NoisyObservationSource(world, config, seed=11), world.grid)
    cloud = noisy.point_cloud()
    low = (cloud.points[:, 2] < 0.015) & (cloud.points[:, 2] > 0.003)
    assert low.sum() > 1000  # the noise does lift table points above a 3 mm band
    unlabelled_low = low & (cloud.labels == NO_OBJECT)
    assert unlabelled_low.sum() < 0.01 * low.sum()
    # and the blue block's layer is open around it: most voxels there are free
    occ = noisy.scene_occupancy("blue block", holding=False, ignore_table=True)
    k = world.grid.world_to_voxel(np.array([[-0.2, -0.1, 0.025]]))[0][2]
    assert occ[:, :, k].mean() < 0.05
