"""Anchor an affordance that moves with the entity itself ("a point 5 cm above the gripper").

Value-map programs are re-run at every replanning step (paper Sec. 3.3). A target defined
relative to a fixed object follows that object if it is displaced — the point of closed-loop
replanning. A target defined relative to the *entity being moved* would run away from it at every
step: the gripper chasing "a point 5 cm above the gripper", a pushed block chasing "12 cm in front
of the block". :class:`SelfRelativeAnchor` detects that case — since the first evaluation the
target has moved with the entity (same displacement, within ``tolerance_m``) while the entity has
moved more than ``min_motion_m`` — and from then on returns the map of the first evaluation.
Targets that move on their own (a displaced block) are never anchored.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.valuemaps.voxel_ops import nonzero_voxels


def _target(grid: VoxelGrid, affordance: NDArray[Any]) -> NDArray[np.float64] | None:
    """World position [m] of the mean of the map's highest voxels, or None for an empty map."""
    arr = np.asarray(affordance)
    peak = float(arr.max()) if arr.size else 0.0
    if peak <= 0:
        return None
    return grid.voxel_to_world(nonzero_voxels(arr >= peak).mean(axis=0))


class SelfRelativeAnchor:
    """Wraps an affordance source (array or callable → array on ``grid``, shape ``grid.shape``).

    Args:
        source: the affordance map or a callable re-evaluating it.
        entity_position: callable returning the entity's current position [m], shape (3,).
        grid: the workspace grid of the maps.
        tolerance_m: how closely the target's displacement must match the entity's [m] (voxel
            rounding moves a target in ~1 cm steps).
        min_motion_m: the entity must have moved this far before anchoring is considered [m].
    """

    def __init__(self, source: Any, entity_position: Callable[[], NDArray[np.float64]],
                 grid: VoxelGrid, tolerance_m: float = 0.015, min_motion_m: float = 0.03) -> None:
        self.source = source
        self.entity_position = entity_position
        self.grid = grid
        self.tolerance_m = tolerance_m
        self.min_motion_m = min_motion_m
        self.anchored = False
        self._first: tuple[NDArray[Any], NDArray[np.float64], NDArray[np.float64]] | None = None

    def __call__(self) -> NDArray[Any]:
        """The current map, or the first one once the target is found to move with the entity."""
        if self.anchored and self._first is not None:
            return self._first[0]
        current = self.source() if callable(self.source) else self.source
        if not callable(self.source):
            return current
        here = np.asarray(self.entity_position(), dtype=np.float64)
        target = _target(self.grid, current)
        if target is None:
            return current
        if self._first is None:
            self._first = (np.array(current, copy=True), target, here)
            return current
        first_map, first_target, first_here = self._first
        moved = here - first_here
        if (float(np.linalg.norm(moved)) > self.min_motion_m
                and float(np.linalg.norm(target - first_target - moved)) <= self.tolerance_m):
            self.anchored = True
            return first_map
        return current
