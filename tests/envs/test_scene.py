"""The scene: every element named, registry names, deterministic resets, 1 s without warnings."""

import mujoco
import numpy as np
import pytest

from voxposer.envs import COLORS, OBJECTS, SceneLayout, TabletopWorld, WorldConfig
from voxposer.envs.registry import body_of
from voxposer.errors import ConfigError, LayoutError


def test_every_element_is_named(world: TabletopWorld) -> None:
    m = world.model
    for kind, count in [(mujoco.mjtObj.mjOBJ_BODY, m.nbody), (mujoco.mjtObj.mjOBJ_GEOM, m.ngeom),
                        (mujoco.mjtObj.mjOBJ_JOINT, m.njnt), (mujoco.mjtObj.mjOBJ_ACTUATOR, m.nu),
                        (mujoco.mjtObj.mjOBJ_CAMERA, m.ncam), (mujoco.mjtObj.mjOBJ_SITE, m.nsite)]:
        names = [mujoco.mj_id2name(m, kind, i) for i in range(count)]
        assert all(names), f"unnamed {kind}"
        assert len(set(names)) == len(names)


def test_scene_has_the_papers_objects(world: TabletopWorld) -> None:
    m = world.model
    for colour in COLORS:
        assert m.body(f"{colour}_block").id > 0
        line = m.geom(f"{colour}_line_geom")
        assert line.contype[0] == 0 and line.conaffinity[0] == 0
    for which in ("top", "middle", "bottom"):
        assert m.joint(f"{which}_drawer_joint").type[0] == mujoco.mjtJoint.mjJNT_SLIDE
        assert m.body(f"{which}_drawer_handle").id > 0
    assert m.ncam == 4
    size = m.geom("blue_block_geom").size
    np.testing.assert_allclose(size, 0.025)


def test_every_registry_object_maps_to_a_body_with_geoms(world: TabletopWorld) -> None:
    labels = set(world.registry.geom_labels.tolist())
    for k, obj in enumerate(OBJECTS):
        assert world.model.body(body_of(obj)).id > 0
        assert k in labels, obj.name


def test_robot_faces_front_from_the_back(fresh: TabletopWorld) -> None:
    # a reset world: body positions are computed (a never-reset world's are all zero)
    base = fresh.data.xpos[fresh.model.body("panda_base").id]
    assert base[0] < -0.5 and abs(base[1]) < 1e-9


def _state(w: TabletopWorld) -> np.ndarray:
    return np.concatenate([w.data.qpos, w.data.qvel, w.data.mocap_pos.ravel()])


def test_same_seed_same_state_different_seed_differs(world: TabletopWorld) -> None:
    world.reset(np.random.default_rng(7))
    a, names_a = _state(world), world.object_names
    world.reset(np.random.default_rng(8))
    b = _state(world)
    world.reset(np.random.default_rng(7))
    np.testing.assert_array_equal(a, _state(world))
    assert world.object_names == names_a
    assert not np.array_equal(a, b)


def test_the_object_list_does_not_tell_which_blocks_a_layout_named(world: TabletopWorld) -> None:
    """A task's layout places its named blocks first; the scene lists blocks and lines by
    name, so a prompt's object list gives no hint of the block an instruction refers to."""
    for named in (("yellow",), ("blue",)):
        world.reset(np.random.default_rng(3), SceneLayout(blocks=named, lines=("pink",),
                                                          extra_blocks=(3, 3)))
        blocks = [n for n in world.object_names if n.endswith(" block")]
        lines = [n for n in world.object_names if n.endswith(" line")]
        assert blocks == sorted(blocks) and len(blocks) == 4 and f"{named[0]} block" in blocks
        assert lines == sorted(lines)


def test_layout_places_required_objects_apart_and_reachable(world: TabletopWorld) -> None:
    layout = SceneLayout(blocks=("blue", "red block"), lines=("green",), extra_blocks=(5, 5),
                         drawer_openings={"top": 0.1}, poses={"blue block": (0.0, -0.2, 0.0)})
    placement = world.reset(np.random.default_rng(1), layout)
    assert {"blue", "red"} <= set(placement.blocks) and "green" in placement.lines
    assert len(placement.blocks) == 7
    np.testing.assert_allclose(world.object_position("blue block")[:2], (0.0, -0.2), atol=2e-3)
    xy = np.array([world.object_position(f"{c} block")[:2] for c in placement.blocks])
    dist = np.linalg.norm(xy[:, None] - xy[None], axis=-1) + np.eye(len(xy))
    assert dist.min() > 0.06
    assert world.drawer_opening("top") == pytest.approx(0.1, abs=0.01)
    for c in COLORS:
        if c not in placement.blocks:
            assert f"{c} block" not in world.object_names


def test_bad_layouts_and_configs_raise() -> None:
    with pytest.raises(LayoutError):
        SceneLayout(blocks=("magenta",))
    with pytest.raises(LayoutError):
        SceneLayout(drawer_openings={"top": 0.5})
    with pytest.raises(ConfigError, match="timestep"):
        WorldConfig(timestep=-1.0)


def test_overlapping_hand_placed_blocks_raise(world: TabletopWorld) -> None:
    layout = SceneLayout(poses={"blue block": (0.0, 0.0), "red block": (0.01, 0.0)})
    with pytest.raises(LayoutError):
        world.reset(np.random.default_rng(0), layout)


def test_steps_one_second_without_warnings(fresh: TabletopWorld) -> None:
    before = [w.number for w in fresh.data.warning]
    fresh.advance(round(1.0 / fresh.config.timestep))
    assert [w.number for w in fresh.data.warning] == before
    assert np.all(np.isfinite(fresh.data.qpos))
