"""detect() from the fused point cloud agrees with the simulator; views agree with each other."""

import numpy as np
import pytest
from tests.perceive import perceive

from voxposer.catalog import label_of
from voxposer.envs import COLORS, SceneLayout, TabletopWorld
from voxposer.errors import UnknownObjectError


@pytest.fixture(scope="module")
def all_blocks(world: TabletopWorld) -> TabletopWorld:
    layout = SceneLayout(blocks=tuple(COLORS)[:8], extra_blocks=(0, 0), extra_lines=(2, 2))
    world.reset(np.random.default_rng(4), layout)
    return world


def test_detect_centres_match_bodies(all_blocks: TabletopWorld) -> None:
    for name in all_blocks.object_names:
        if name.endswith(" block"):
            found = perceive(all_blocks).detect(name)
            np.testing.assert_allclose(found.position, all_blocks.object_position(name), atol=0.01)


def test_detected_object_reads_like_a_dict(all_blocks: TabletopWorld) -> None:
    obj = perceive(all_blocks).detect("The Blue Block")
    assert obj["position"] is obj.position
    assert obj["occupancy"].shape == all_blocks.grid.shape and obj["occupancy"].any()
    assert obj["aabb"].shape == (2, 3) and obj["points"].shape[1] == 3
    assert np.linalg.norm(obj["normal"]) == pytest.approx(1.0)
    with pytest.raises(KeyError):
        obj["colour"]


def test_parts_are_detected(all_blocks: TabletopWorld) -> None:
    handle = perceive(all_blocks).detect("top drawer handle")
    drawer = perceive(all_blocks).detect("top drawer")
    cabinet = perceive(all_blocks).detect("cabinet")
    assert len(handle.points) < len(drawer.points) < len(cabinet.points)
    np.testing.assert_allclose(handle.position, all_blocks.object_position("top drawer handle"),
                               atol=0.02)
    assert handle.normal[1] < -0.5  # the handle faces −y, out of the cabinet


def test_views_agree_on_a_block(all_blocks: TabletopWorld) -> None:
    cloud = perceive(all_blocks).point_cloud()
    label = label_of("blue block")
    centres = []
    for cam in range(4):
        pts = cloud.points[(cloud.labels == label) & (cloud.camera == cam)]
        if len(pts) == 0:
            continue  # occluded from this camera
        top = pts[pts[:, 2] > pts[:, 2].max() - 0.002]  # the top face
        if len(top) > 20:
            centres.append(top.mean(axis=0))
    assert len(centres) >= 2
    centres = np.array(centres)
    assert np.max(np.linalg.norm(centres - centres.mean(axis=0), axis=1)) < 0.01


def test_observation_contents(all_blocks: TabletopWorld) -> None:
    obs = all_blocks.observe()
    assert len(obs.cameras) == 4
    for frame in obs.cameras:
        h, w = frame.depth.shape
        assert frame.rgb.shape == (h, w, 3) and frame.object_ids.shape == (h, w)
        assert frame.intrinsics.shape == (3, 3) and frame.extrinsics.shape == (4, 4)
        # The camera looks at the workspace centre along its +z axis.
        view = frame.extrinsics[:3, 2]
        to_target = np.array(all_blocks.config.cameras.target) - frame.extrinsics[:3, 3]
        assert np.dot(view, to_target / np.linalg.norm(to_target)) > 0.999
        assert np.isfinite(frame.depth).any()
    cloud = perceive(all_blocks).point_cloud()
    assert all_blocks.grid.contains(cloud.points).all()
    assert cloud.normals.shape == cloud.points.shape


def test_unknown_and_absent_names_raise(all_blocks: TabletopWorld) -> None:
    with pytest.raises(UnknownObjectError, match="blue block"):
        perceive(all_blocks).detect("unicorn")
    absent = next(c for c in COLORS if f"{c} block" not in all_blocks.object_names)
    with pytest.raises(UnknownObjectError):
        perceive(all_blocks).detect(f"{absent} block")


@pytest.mark.parametrize("which", ["top", "middle", "bottom"])
def test_a_handles_normal_faces_out_of_the_cabinet(world: TabletopWorld, which: str) -> None:
    # the cameras see mostly a handle's top; its normal must still point the way it opens
    world.reset(np.random.default_rng(8), SceneLayout(blocks=("blue",), extra_blocks=(0, 0),
                                                      drawer_openings={which: 0.12}))
    normal = perceive(world).detect(f"{which} drawer handle").normal
    assert normal @ world.drawer_axis(f"{which} drawer") > np.cos(np.radians(10))
    assert abs(normal[2]) < 1e-9


@pytest.mark.parametrize("opening", [0.0, 0.12])
def test_a_drawers_sliding_direction_comes_from_what_the_cameras_see(
        world: TabletopWorld, opening: float) -> None:
    # perception's direction (the front's outward normal) agrees with the simulator's joint
    world.reset(np.random.default_rng(9), SceneLayout(blocks=("blue",), extra_blocks=(0, 0),
                                                      drawer_openings={"middle": opening}))
    truth = world.drawer_axis("middle drawer")
    for part in ("middle drawer", "middle drawer handle"):
        axis = perceive(world).sliding_axis(part)
        assert axis is not None and axis @ truth > np.cos(np.radians(10)), (part, axis, truth)
    assert perceive(world).sliding_axis("blue block") is None


def test_an_object_is_detected_once_per_observation(world: TabletopWorld) -> None:
    world.reset(np.random.default_rng(5), SceneLayout(blocks=("blue",), extra_blocks=(0, 0)))
    perceiver = perceive(world)
    first = perceiver.detect("blue block")
    assert perceiver.detect("the blue block") is first  # same observation: the same detection
    assert not first.points.flags.writeable  # shared, so read-only
    world.move_to_pose(world.get_ee_pose()[0] + [0.0, 0.05, 0.0])  # time passes: a new view
    again = perceiver.detect("blue block")
    assert again is not first
    np.testing.assert_allclose(again.position, first.position, atol=0.005)
