"""Disturbances change what they claim to; the Gymnasium wrapper resets and steps."""

import numpy as np
import pytest
from tests.perceive import perceive

from voxposer.envs import TOP_DOWN_QUAT, SceneLayout, TabletopEnv, TabletopWorld
from voxposer.errors import InvalidActionError


def test_force_moves_the_robot(world: TabletopWorld) -> None:
    world.reset(np.random.default_rng(0), SceneLayout(extra_blocks=(0, 0), cabinet=False))
    world.advance(50)
    q0 = world.data.qpos[:7].copy()
    record = world.push_robot(np.random.default_rng(1), magnitude=(60.0, 60.0), duration=0.2,
                              link="panda_link5")
    assert record.kind == "force" and np.linalg.norm(record.after) == pytest.approx(60.0)
    world.advance(50)
    assert np.max(np.abs(world.data.qpos[:7] - q0)) > 1e-3


def test_displace_object_moves_it(fresh: TabletopWorld) -> None:
    record = fresh.displace_object(np.random.default_rng(2))
    now = fresh.object_position(record.target)
    np.testing.assert_allclose(now[:2], record.after[:2], atol=1e-6)
    assert np.linalg.norm(record.after[:2] - record.before[:2]) >= 0.08
    np.testing.assert_allclose(perceive(fresh).detect(record.target).position[:2], now[:2], atol=0.01)


def test_revert_progress_opens_a_drawer(fresh: TabletopWorld) -> None:
    record = fresh.revert_progress(np.random.default_rng(3), "top drawer")
    assert record.before[0] == pytest.approx(0.0, abs=1e-3)
    assert fresh.drawer_opening("top") == pytest.approx(record.after[0]) and record.after[0] >= 0.1


def test_gym_env_reset_and_step() -> None:
    env = TabletopEnv(max_steps=3)
    try:
        obs, _ = env.reset(seed=5)
        again, _ = env.reset(seed=5)
        np.testing.assert_array_equal(obs["ee_position"], again["ee_position"])
        assert env.observation_space.contains(obs)
        action = np.concatenate([obs["ee_position"] + [0.0, 0.0, -0.02], TOP_DOWN_QUAT, [0.0]])
        assert env.action_space.contains(action)
        for _ in range(3):
            obs, _, terminated, truncated, _ = env.step(action)
        assert truncated and not terminated
        with pytest.raises(InvalidActionError):
            env.step(np.full(8, np.nan))
    finally:
        env.close()
