"""The LLM + Primitives baseline never drops a failed move: a move that ends away from its
target raises, naming the target and the miss (the official release logged and went on)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from voxposer.bench.primitives import Primitives
from voxposer.errors import MoveMissedError
from voxposer.robot import MoveResult


class _BlockedArm:
    """A test double of a robot: moves stop 4 cm short of any target beyond x = 0.1 m."""

    def __init__(self) -> None:
        self.ee = np.array([0.0, 0.0, 0.3])

    def get_ee_pose(self):
        return self.ee.copy(), np.array([0.0, 0.0, 0.0, 1.0])

    def move_to_pose(self, position, quat=None, speed_scale=1.0):
        target = np.asarray(position, dtype=float)
        short = 0.04 if target[0] > 0.1 else 0.0
        self.ee = target - np.array([short, 0.0, 0.0])
        return MoveResult(short == 0.0, short, 0.0, 1.0)


def test_a_blocked_move_raises_with_the_target_and_the_miss() -> None:
    prims = Primitives(_BlockedArm(), SimpleNamespace(), max_speed_scale=3.0)
    prims.move_to_pos([0.05, 0.0, 0.2])  # reachable: no error
    with pytest.raises(MoveMissedError, match=r"0\.2.*4\.0 cm") as info:
        prims.move_to_pos([0.2, 0.0, 0.2])
    assert info.value.position_error == pytest.approx(0.04)
    assert info.value.position == [0.2, 0.0, 0.2]
