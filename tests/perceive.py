"""Test helper: the ground-truth segmentation perceiver of a world, one per world."""

from __future__ import annotations

from functools import cache
from typing import Any

from voxposer.perception import SegmentationPerceiver


@cache
def perceive(world: Any) -> SegmentationPerceiver:
    """The (cached) perceiver reading ``world``'s observations."""
    return SegmentationPerceiver(world, world.grid)
