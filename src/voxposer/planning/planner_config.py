"""Parameters of the path planner (paper Sec. 4, "Motion Planner"), validated."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from voxposer.config_checks import require_non_negative
from voxposer.errors import ConfigError
from voxposer.valuemaps.cost import CostMapConfig

PlanMethod = Literal["global", "greedy"]


@dataclass(frozen=True)
class PlannerConfig:
    """Planner parameters.

    Attributes:
        method: ``"global"`` (A*, default) or ``"greedy"`` (the paper's release, for comparison).
        cost: cost-map composition parameters (paper values by default).
        length_weight: cost per voxel travelled, added to the cost map (keeps paths short).
        waypoint_spacing_m: distance between consecutive waypoints [m].
        savgol_window: Savitzky–Golay window [waypoints], odd.
        savgol_polyorder: Savitzky–Golay polynomial order.
        greedy_radius: neighbourhood half-size of the greedy mode [voxels] (release: 2).
        greedy_max_steps: step limit of the greedy mode (release: 300).
        grasp_approach_m: a path that ends closing the gripper (a grasp) ends with a straight
            approach along the hand's approach axis from this far before the target [m] (top-down:
            a vertical descent); 0 disables it.
        grasp_approach_radius_m: path points within this distance of that approach line and
            less than ``grasp_approach_m`` before the target are replaced by it [m]; the open
            fingers span ≈ 9 cm, so a slanted approach within it catches the object's edge and
            tilts it.
        shortcut: straighten the found path where a straight segment costs no more
            (:mod:`voxposer.planning.shortcut`; global method only).
        shortcut_keeps_distance: a straightened segment also comes no nearer what the
            avoidance map avoids than the run it replaces (off until measured on the whole
            test suite and with the default model; dev records
            ``benchmarks/results/dev-2026-12-07/``).
    """

    method: PlanMethod = "global"
    cost: CostMapConfig = field(default_factory=CostMapConfig)
    length_weight: float = 0.1
    waypoint_spacing_m: float = 0.01
    savgol_window: int = 11
    savgol_polyorder: int = 3
    greedy_radius: int = 2
    greedy_max_steps: int = 300
    grasp_approach_m: float = 0.06
    grasp_approach_radius_m: float = 0.06
    shortcut: bool = True
    shortcut_keeps_distance: bool = False

    def __post_init__(self) -> None:
        if self.method not in ("global", "greedy"):
            raise ConfigError(
                f"PlannerConfig.method must be 'global' or 'greedy'; got {self.method!r}"
            )
        if not np.isfinite(self.length_weight) or self.length_weight <= 0:
            raise ConfigError(
                f"PlannerConfig.length_weight must be > 0; got {self.length_weight!r}"
            )
        if not np.isfinite(self.waypoint_spacing_m) or not 1e-4 <= self.waypoint_spacing_m <= 0.5:
            raise ConfigError(
                f"PlannerConfig.waypoint_spacing_m must be in [0.0001, 0.5] m; got {self.waypoint_spacing_m!r}"
            )
        if self.savgol_window < 1 or self.savgol_window % 2 == 0:
            raise ConfigError(
                f"PlannerConfig.savgol_window must be a positive odd int; got {self.savgol_window!r}"
            )
        if not 0 <= self.savgol_polyorder < max(self.savgol_window, 1):
            raise ConfigError(
                f"PlannerConfig.savgol_polyorder must be in [0, savgol_window); got {self.savgol_polyorder!r}"
            )
        if self.greedy_radius < 1 or self.greedy_max_steps < 1:
            raise ConfigError("PlannerConfig.greedy_radius and greedy_max_steps must be >= 1")
        require_non_negative(self, "grasp_approach_m", "grasp_approach_radius_m")
