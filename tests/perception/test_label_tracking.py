"""The pixel perception's tracker: labels carried between detections follow a block moved by
a centimetre, give up (and detect afresh) when it jumps, near the cabinet, with the hand at a
gray object, and when due."""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest

from voxposer import catalog
from voxposer.envs import SceneLayout, TabletopWorld
from voxposer.errors import ConfigError
from voxposer.perception.colour_depth import ColourDepthPerceiver
from voxposer.perception.label_tracking import LabelTrackingConfig, track_labels
from voxposer.perception.pixel_labels import label_pixels

BLUE, GREEN = (-0.15, -0.10), (0.05, -0.10)
LAYOUT = SceneLayout(blocks=("blue", "green"), lines=("yellow",),
                     poses={"blue block": BLUE, "green block": GREEN,
                            "yellow line": (-0.05, 0.10, 0.4)},
                     extra_blocks=(0, 0), extra_lines=(0, 0))
SLOW = LabelTrackingConfig(redetect_s=100.0)  # detections only when tracking gives up


def _move(world: TabletopWorld, name: str, dx: float) -> np.ndarray:
    """Set ``name`` down ``dx`` [m] further along x, at rest; its new position [m]."""
    joint = world.model.joint(f"{name.split()[0]}_block_joint")
    adr, dof = joint.qposadr[0], joint.dofadr[0]
    world.data.qpos[adr] += dx
    world.data.qvel[dof:dof + 6] = 0.0
    mujoco.mj_forward(world.model, world.data)
    world.advance(1)  # a new observation
    return world.object_position(name)


@pytest.fixture
def tracked(world: TabletopWorld) -> ColourDepthPerceiver:
    world.reset(np.random.default_rng(5), LAYOUT)
    perceiver = ColourDepthPerceiver(world, world.grid, tracking=SLOW)
    perceiver.point_cloud()  # the first detection
    return perceiver


def test_a_still_scene_is_carried_with_the_detections_labels(
        tracked: ColourDepthPerceiver, world: TabletopWorld) -> None:
    world.advance(20)
    cloud = tracked.point_cloud()
    assert tracked.carried == [False, True]
    fresh = label_pixels(tracked.observe(), world.grid).cloud.labels
    for name in ("blue block", "green block", "yellow line"):
        k = catalog.label_of(name)
        both = np.count_nonzero((cloud.labels == k) & (fresh == k))
        assert both >= 0.95 * np.count_nonzero(fresh == k), name
        assert np.count_nonzero(cloud.labels == k) <= 1.05 * np.count_nonzero(fresh == k), name
    found = tracked.detect("blue block")
    assert np.linalg.norm(found.position - world.object_position("blue block")) < 0.015


def test_a_block_pushed_a_centimetre_a_step_is_followed(
        tracked: ColourDepthPerceiver, world: TabletopWorld) -> None:
    start = world.object_position("blue block")
    for _ in range(4):
        now = _move(world, "blue block", 0.01)
        found = tracked.detect("blue block")
    assert tracked.carried[1:] == [True] * 4  # never detected afresh
    assert np.linalg.norm(found.position - now) < 0.015
    assert np.linalg.norm(found.position - start) > 0.03  # it moved with the block


def test_a_block_that_jumps_5_cm_is_detected_afresh(
        tracked: ColourDepthPerceiver, world: TabletopWorld) -> None:
    previous = label_pixels(tracked.observe(), world.grid)
    now = _move(world, "blue block", 0.05)
    assert track_labels(tracked.observe(), world.grid, previous, SLOW,
                        previous.unexplained) is None  # the blue block lost its points
    found = tracked.detect("blue block")
    assert tracked.carried == [False, False]
    assert np.linalg.norm(found.position - now) < 0.015


def test_a_detection_runs_when_due(world: TabletopWorld) -> None:
    world.reset(np.random.default_rng(5), LAYOUT)
    perceiver = ColourDepthPerceiver(world, world.grid, tracking=LabelTrackingConfig(
        redetect_s=0.5))
    perceiver.point_cloud()
    for _ in range(4):  # 0.2 s of simulated time each
        world.advance(round(0.2 / world.model.opt.timestep))
        perceiver.point_cloud()
    assert perceiver.carried == [False, True, True, False, True]


def test_the_hand_near_the_cabinet_detects_afresh(tracked: ColourDepthPerceiver,
                                                  world: TabletopWorld) -> None:
    previous = label_pixels(tracked.observe(), world.grid)
    handle = tracked.detect("top drawer handle").position
    obs = tracked.observe()
    near = dataclasses.replace(obs, ee_position=handle + [0.0, 0.0, 0.05])
    assert track_labels(near, world.grid, previous, SLOW, previous.unexplained) is None
    assert track_labels(obs, world.grid, previous, SLOW, previous.unexplained) is not None


def test_the_hand_at_the_gray_block_detects_afresh(world: TabletopWorld) -> None:
    """The gray gripper's points beside the gray block cannot be told from the block's by
    colour: carrying them (or dropping the block's as the gripper's, a few each step) drifted
    the block's centre to the hand's; a chromatic block by the hand is still carried."""
    world.reset(np.random.default_rng(5), dataclasses.replace(
        LAYOUT, blocks=("blue", "gray"), poses={"blue block": BLUE, "gray block": GREEN,
                                                "yellow line": (-0.05, 0.10, 0.4)}))
    perceiver = ColourDepthPerceiver(world, world.grid, tracking=SLOW)
    previous = label_pixels(perceiver.observe(), world.grid)
    obs = perceiver.observe()
    for name, side, carried in (("gray block", 1, False), ("blue block", -1, True)):
        beside = world.object_position(name) + [side * 0.13, 0.0, 0.035]  # at its outer edge
        hand = dataclasses.replace(obs, ee_position=beside)
        out = track_labels(hand, world.grid, previous, SLOW, previous.unexplained)
        assert (out is not None) is carried, name
    assert track_labels(obs, world.grid, previous, SLOW, previous.unexplained) is not None


@pytest.mark.parametrize("field, value", [("redetect_s", 0.0), ("reach_voxels", 4),
                                          ("keep_fraction", 1.5), ("near_cabinet_m", -0.1)])
def test_bad_tracking_settings_are_refused_naming_them(field: str, value: float) -> None:
    with pytest.raises(ConfigError, match=f"{field}={value!r}"):
        LabelTrackingConfig(**{field: value})


def test_tracking_is_for_the_pixel_perceptions_only(world: TabletopWorld) -> None:
    from voxposer.pipeline import simulated_perceiver

    tracked = simulated_perceiver(world, "colour-depth-noisy", tracking=SLOW)
    assert isinstance(tracked, ColourDepthPerceiver) and tracked.tracking is SLOW
    named = simulated_perceiver(world, "colour-depth-tracked-noisy")
    assert isinstance(named, ColourDepthPerceiver)
    assert named.tracking == LabelTrackingConfig()
    untracked = simulated_perceiver(world, "colour-depth-noisy")
    assert isinstance(untracked, ColourDepthPerceiver) and untracked.tracking is None
    with pytest.raises(ConfigError, match="'ground-truth' reads the simulator's labels"):
        simulated_perceiver(world, "ground-truth", tracking=SLOW)
