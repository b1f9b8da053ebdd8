"""Shared fixtures: one tabletop world per test session (EGL offscreen rendering)."""

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import numpy as np
import pytest

from voxposer.envs import SceneLayout, TabletopWorld


@pytest.fixture(scope="session")
def world() -> TabletopWorld:
    w = TabletopWorld()
    yield w
    w.close()


@pytest.fixture
def fresh(world: TabletopWorld) -> TabletopWorld:
    """The shared world reset with a seeded default layout."""
    world.reset(np.random.default_rng(0), SceneLayout())
    return world
