"""Layout helpers of the multi-step suite: blocks placed clear of places and of each other.

A step must not hold at reset and no step's motion may pass through a later step's condition
(the order check takes the first sample a condition holds), so blocks stand well outside the
regions the end effector is later sent to, and apart from each other.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import sample_xy
from voxposer.errors import LayoutError
from voxposer.places import get_place

#: Box [m] where blocks the gripper hovers over or grasps stand (reachable top-down).
BLOCK_LO, BLOCK_HI = (-0.30, -0.25), (0.05, 0.25)
#: How far [m] a block stands outside a place the end effector is later sent to (its hover
#: point, 15 cm up, must not count as "at" that place).
OUTSIDE_M = 0.12
#: Least distance [m] between two blocks the steps name.
APART_M = 0.20
#: Horizontal radius [m] kept free of distractors around a block the gripper hovers over.
HOVER_CLEAR_M = 0.08


def outside(place: str, gap: float = OUTSIDE_M) -> Callable[[np.ndarray], bool]:
    """A predicate: (x, y) [m] lies at least ``gap`` outside ``place`` (a side's band, or a
    corner's disc of ``corner_radius_m``)."""
    p, radius = get_place(place), Tolerances().corner_radius_m
    return lambda xy: bool(p.margin(xy, radius) <= -gap)


def apart(*others: tuple[float, float], gap: float = APART_M) -> Callable[[np.ndarray], bool]:
    """A predicate: (x, y) [m] lies at least ``gap`` from every point of ``others``."""
    return lambda xy: all(math.dist(xy, o) >= gap for o in others)


def place_block(rng: np.random.Generator, *tests: Callable[[np.ndarray], bool],
                lo: tuple[float, float] = BLOCK_LO, hi: tuple[float, float] = BLOCK_HI,
                what: str = "a block") -> tuple[float, float]:
    """A reachable (x, y) [m] in the box [lo, hi] that passes every test.

    Raises:
        LayoutError: no such point after many draws (the reset tries another layout).
    """
    def ok(xy: np.ndarray) -> bool:
        return all(t(xy) for t in tests)

    xy = sample_xy(rng, lo, hi, ok)
    if not ok(np.asarray(xy)):
        raise LayoutError(f"no place for {what} in the box {lo}–{hi} passing its tests")
    return xy


def hover_clear(xy: tuple[float, float]) -> list[tuple[tuple[float, float], float]]:
    """``keep_clear`` discs for a block the gripper hovers over."""
    return [(xy, HOVER_CLEAR_M)]
