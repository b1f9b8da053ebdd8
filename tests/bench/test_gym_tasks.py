"""Every benchmark task is a registered Gymnasium environment whose success is the task's own
check (no LLM, no planner: the test drives the end effector with plain pose actions)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import voxposer.bench  # noqa: F401  (registers the environments)
from voxposer.bench import TASKS
from voxposer.bench.gym_ids import env_id
from voxposer.envs import TOP_DOWN_QUAT
from voxposer.places import get_place


def test_every_task_is_registered_under_the_namespace() -> None:
    ids = {env_id(name) for name in TASKS}
    assert len(ids) == 13 and ids <= set(gym.registry)
    assert env_id("push_to_pos") == "voxposer/PushToPos-v0"


@pytest.fixture(scope="module")
def region_env():
    env = gym.make("voxposer/MoveToRegion-v0", split="unseen", max_steps=400)
    yield env
    env.close()


def test_reset_is_the_benchmark_episode_and_success_is_the_tasks_check(region_env) -> None:
    obs, info = region_env.reset(seed=7)
    assert info["seed"] == 7 and info["instruction"].startswith("move to the ")
    assert info["attributes"]["region"] in info["instruction"]
    _, again = region_env.reset(seed=7)
    assert again["instruction"] == info["instruction"]  # same seed, same episode
    place = get_place(info["attributes"]["region"])
    hover = np.array([*place.point, 0.05])
    stay = np.concatenate([obs["ee_position"], TOP_DOWN_QUAT, [0.0]])
    _, reward, terminated, _, step_info = region_env.step(stay)
    assert reward == 0.0 and not terminated and not step_info["success"]  # not there yet
    go = np.concatenate([hover, TOP_DOWN_QUAT, [0.0]])
    for _ in range(400):
        _, reward, terminated, truncated, step_info = region_env.step(go)
        if terminated or truncated:
            break
    assert terminated and reward == 1.0 and step_info["success"], step_info["reason"]
