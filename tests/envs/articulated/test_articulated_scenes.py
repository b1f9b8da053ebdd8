"""Every articulated task: named elements, seeded resets, labelled views, success checks, 1 s of
stable physics, and configuration errors naming the field."""

import math
from collections.abc import Callable

import mujoco
import numpy as np
import pytest

from voxposer.envs.articulated import TASKS, ArticulatedConfig, ArticulatedWorld, DoorConfig
from voxposer.envs.ik import HOME_Q
from voxposer.errors import ConfigError, LayoutError, UnknownObjectError
from voxposer.robot import Robot

World = Callable[[str], ArticulatedWorld]


def _state(world: ArticulatedWorld) -> np.ndarray:
    d = world.data
    return np.concatenate([d.qpos, d.qvel, d.mocap_pos.ravel(), d.mocap_quat.ravel()])


@pytest.mark.parametrize("task", TASKS)
def test_every_element_is_named_and_the_world_is_a_robot(articulated: World, task: str) -> None:
    world = articulated(task)
    m = world.model
    for kind, count in [(mujoco.mjtObj.mjOBJ_BODY, m.nbody), (mujoco.mjtObj.mjOBJ_GEOM, m.ngeom),
                        (mujoco.mjtObj.mjOBJ_JOINT, m.njnt), (mujoco.mjtObj.mjOBJ_ACTUATOR, m.nu),
                        (mujoco.mjtObj.mjOBJ_CAMERA, m.ncam), (mujoco.mjtObj.mjOBJ_SITE, m.nsite),
                        (mujoco.mjtObj.mjOBJ_LIGHT, m.nlight)]:
        names = [mujoco.mj_id2name(m, kind, i) for i in range(count)]
        assert all(names), f"unnamed {kind}"
        assert len(set(names)) == len(names)
    assert m.ncam == 4
    assert isinstance(world, Robot)
    assert world.label_names[:3] == world.object.parts
    assert world.label_names[3:] == ("table", "robot", "gripper")


@pytest.mark.parametrize("task", TASKS)
def test_same_seed_same_state_different_seed_differs(articulated: World, task: str) -> None:
    world = articulated(task)
    first = world.reset(np.random.default_rng(7))
    a = _state(world)
    world.reset(np.random.default_rng(8))
    b = _state(world)
    again = world.reset(np.random.default_rng(7))
    np.testing.assert_array_equal(a, _state(world))
    assert again == first
    assert not np.array_equal(a, b)


@pytest.mark.parametrize("task", TASKS)
def test_reset_stays_within_the_stated_ranges(articulated: World, task: str) -> None:
    world = articulated(task)
    cfg = world.config
    for seed in range(5):
        placement = world.reset(np.random.default_rng(seed))
        offset = np.subtract(placement.object_xy, world.object.nominal_xy)
        assert np.all(np.abs(offset) <= cfg.position_noise)
        assert abs(placement.object_yaw) <= cfg.yaw_noise
        assert np.all(np.abs(np.subtract(placement.arm_q, HOME_Q)) <= cfg.joint_noise + 1e-9)
        np.testing.assert_allclose(world.joint_positions(), placement.arm_q, atol=0.02)
        state = world.articulation_state()
        assert all(abs(v) < math.radians(0.5) for v in state.values()), state
        assert not world.success()[0]


@pytest.mark.parametrize("task", TASKS)
def test_every_part_is_labelled_in_the_views(articulated: World, task: str) -> None:
    world = articulated(task)
    world.reset(np.random.default_rng(0))
    obs = world.observe(rgb=False)
    assert obs.label_names == world.label_names
    assert len(obs.cameras) == 4
    for k, part in enumerate(world.object.parts):
        pixels = [int(np.sum(frame.object_ids == k)) for frame in obs.cameras]
        assert max(pixels) >= 50, (part, pixels)
        assert sum(p > 0 for p in pixels) >= 2, (part, pixels)
    for frame in obs.cameras:
        labelled = frame.object_ids >= 0
        assert np.all(np.isfinite(frame.depth[labelled]))


@pytest.mark.parametrize("task", TASKS)
def test_success_passes_when_open_and_fails_just_short(articulated: World, task: str) -> None:
    world = articulated(task)
    world.reset(np.random.default_rng(0))
    key, threshold = world.object.success_key, world.object.success_threshold
    short = threshold - (math.radians(0.5) if key.endswith("_angle") else 0.005)
    world.set_articulation_state({key: short})
    ok, reason = world.success()
    assert not ok
    assert key in reason and "threshold" in reason
    world.set_articulation_state({key: threshold + 0.01})
    ok, reason = world.success()
    assert ok, reason
    shown = f"{math.degrees(threshold):.1f}°" if key.endswith("_angle") else f"{threshold * 100:.1f} cm"
    assert shown in reason


@pytest.mark.parametrize("task", TASKS)
def test_steps_one_second_without_warnings_and_stays_shut(articulated: World, task: str) -> None:
    world = articulated(task)
    world.reset(np.random.default_rng(3))
    calls: list[float] = []
    world.step_callbacks.append(lambda w: calls.append(w.time))
    try:
        before = [w.number for w in world.data.warning]
        start = world.part_position(world.object.parts[1])
        world.advance(round(1.0 / world.config.timestep))
        assert [w.number for w in world.data.warning] == before
        assert np.all(np.isfinite(world.data.qpos))
        assert calls and calls[-1] == pytest.approx(world.time)
        state = world.articulation_state()
        assert all(abs(v) < math.radians(0.5) for v in state.values()), state
        np.testing.assert_allclose(world.part_position(world.object.parts[1]), start, atol=1e-3)
    finally:
        world.step_callbacks.clear()


def test_ground_truth_queries_name_what_is_known(articulated: World) -> None:
    world = articulated("window")
    world.reset(np.random.default_rng(0))
    with pytest.raises(UnknownObjectError, match="window handle"):
        world.part_position("door handle")
    with pytest.raises(LayoutError, match="window_offset"):
        world.set_articulation_state({"door_angle": 0.1})
    with pytest.raises(LayoutError, match="window_offset"):
        world.set_articulation_state({"window_offset": 1.0})
    axis = world.joint_axis("window_offset")
    assert axis.direction[1] < -0.99  # the sash opens to the left (−y)


def test_unknown_task_and_bad_config_raise_naming_the_choice() -> None:
    with pytest.raises(ConfigError, match="door, window, fridge"):
        ArticulatedWorld("oven")
    with pytest.raises(ConfigError, match=r"ArticulatedConfig\.position_noise"):
        ArticulatedConfig(position_noise=-0.01)
    with pytest.raises(ConfigError, match=r"ArticulatedConfig\.yaw_noise"):
        ArticulatedConfig(yaw_noise=1.0)
    with pytest.raises(ConfigError, match=r"DoorConfig\.unlatch_angle"):
        DoorConfig(unlatch_angle=math.radians(60))
    with pytest.raises(ConfigError, match=r"ArticulatedConfig\.timestep"):
        ArticulatedConfig(timestep=0.0)
