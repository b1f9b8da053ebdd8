"""Reading a door's opening, a lever's press and a sash's offset from their points."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from voxposer.errors import ObjectNotVisibleError
from voxposer.perception.articulation import ArticulationEstimator, ArticulationParts


def _slab(yaw: float, rng: np.random.Generator, width: float = 0.4) -> np.ndarray:
    """Points of a 2 cm thick door leaf of ``width`` turned by ``yaw`` about z at the origin."""
    u = rng.uniform(0, width, 400)
    v = rng.uniform(-0.01, 0.01, 400)
    z = rng.uniform(0.0, 0.8, 400)
    return np.column_stack([u * math.cos(yaw) - v * math.sin(yaw),
                            u * math.sin(yaw) + v * math.cos(yaw), z])


def _lever(tilt: float, rng: np.random.Generator) -> np.ndarray:
    s = rng.uniform(0, 0.12, 200)
    return np.column_stack([np.full(200, 0.4), s * math.cos(tilt), 0.5 - s * math.sin(tilt)]) \
        + rng.normal(0, 0.002, (200, 3))


class _Perceiver:
    """Returns whatever points ``scene`` holds for each name (a test double)."""

    def __init__(self) -> None:
        self.scene: dict[str, np.ndarray] = {}

    def detect(self, name: str) -> SimpleNamespace:
        if name not in self.scene:
            raise ObjectNotVisibleError(name)
        return SimpleNamespace(points=self.scene[name])


def test_door_and_lever_angles_follow_the_points() -> None:
    rng = np.random.default_rng(0)
    p = _Perceiver()
    est = ArticulationEstimator(p, ArticulationParts("door handle", hinged="door",
                                                     lever="door handle"))
    p.scene = {"door": _slab(0.3, rng), "door handle": _lever(0.0, rng)}
    est.reset()
    p.scene = {"door": _slab(0.3 + math.radians(25), rng),
               "door handle": _lever(math.radians(35), rng)}
    state = est.estimate()
    assert math.degrees(state["door_angle"]) == pytest.approx(25, abs=1.5)
    assert math.degrees(state["handle_angle"]) == pytest.approx(35, abs=3)
    assert state["handle_position"].shape == (3,)


def test_hidden_part_keeps_its_last_estimate() -> None:
    rng = np.random.default_rng(1)
    p = _Perceiver()
    est = ArticulationEstimator(p, ArticulationParts("door handle", hinged="door"))
    p.scene = {"door": _slab(0.0, rng), "door handle": _lever(0.0, rng)}
    est.reset()
    p.scene = {"door": _slab(0.4, rng), "door handle": _lever(0.0, rng)}
    opened = est.estimate()["door_angle"]
    p.scene = {"door": _slab(0.4, rng)[:3]}  # the arm hides the handle and most of the leaf
    again = est.estimate()
    assert again["door_angle"] == pytest.approx(opened)
    assert math.degrees(opened) == pytest.approx(math.degrees(0.4), abs=1.5)


def test_sash_offset_and_a_part_unseen_at_reset() -> None:
    rng = np.random.default_rng(2)
    p = _Perceiver()
    est = ArticulationEstimator(p, ArticulationParts("window handle", sliding="window"))
    sash = _slab(0.0, rng)
    p.scene = {"window": sash, "window handle": _lever(0.0, rng)}
    est.reset()
    p.scene = {"window": sash + [0.0, 0.15, 0.0], "window handle": _lever(0.0, rng)}
    assert est.estimate()["window_offset"] == pytest.approx(0.15, abs=0.005)
    p.scene = {"window": sash}
    with pytest.raises(ObjectNotVisibleError, match="handle_position not seen"):
        est.reset()
