"""Shared fixtures: one articulated world per task for the whole session (EGL rendering)."""

import os

os.environ.setdefault("MUJOCO_GL", "egl")

from collections.abc import Callable, Iterator

import numpy as np
import pytest

from voxposer.envs.articulated import ArticulatedWorld


@pytest.fixture(scope="session")
def articulated() -> Iterator[Callable[[str], ArticulatedWorld]]:
    """``articulated(task)``: the session's world of ``task``, built on first use."""
    worlds: dict[str, ArticulatedWorld] = {}

    def get(task: str) -> ArticulatedWorld:
        if task not in worlds:
            worlds[task] = ArticulatedWorld(task)
        return worlds[task]

    yield get
    for world in worlds.values():
        world.close()


@pytest.fixture
def door(articulated: Callable[[str], ArticulatedWorld]) -> ArticulatedWorld:
    """The door world, reset with seed 0."""
    world = articulated("door")
    world.reset(np.random.default_rng(0))
    return world


@pytest.fixture
def window(articulated: Callable[[str], ArticulatedWorld]) -> ArticulatedWorld:
    """The window world, reset with seed 0."""
    world = articulated("window")
    world.reset(np.random.default_rng(0))
    return world


@pytest.fixture
def fridge(articulated: Callable[[str], ArticulatedWorld]) -> ArticulatedWorld:
    """The fridge world, reset with seed 0."""
    world = articulated("fridge")
    world.reset(np.random.default_rng(0))
    return world
