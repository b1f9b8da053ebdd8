"""Success tolerances of the 13 tasks — every threshold of every check lives here, once.

Printed at the top of each benchmark report (:meth:`Tolerances.rows`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any

from voxposer.errors import ConfigError


def _default_bands() -> dict[str, tuple[float, float]]:
    return {
        "faster speed": (1.25, math.inf),
        "3x speed": (2.0, math.inf),
        "slower speed": (0.05, 0.8),
        "a quarter of the speed": (0.1, 0.4),
    }


@dataclass(frozen=True)
class Tolerances:
    """Thresholds of the success checks (metres, seconds, or ratios).

    Attributes:
        corner_radius_m: an entity is "at" a corner within this horizontal distance of its point.
        ee_max_height_m: the end effector is "at" a table place no higher than this [m].
        rest_height_m: a block "rests on the table" when its centre is below this height [m].
        above_height_m: "top of [obj]": end effector this far above the block's top face
            (lo, hi) [m].
        above_lateral_m: "top of [obj]": horizontal distance to the block centre at most [m].
        beside_gap_m: "left of [obj]" etc.: distance from the block's face along that side
            (lo, hi) [m].
        beside_lateral_m: … horizontal offset across that side at most [m].
        beside_max_height_m: … end effector height at most [m].
        side_slack_m: "staying on the [preposition] the [obj]": the end effector may cross the
            half-space bounded by the block's face by at most this much, at any time [m].
        min_dist_slack_m: "at least [dist]cm from": the minimum over the whole motion of the
            end effector–block-centre distance must be ≥ dist − this [m].
        speed_window_s: speeds are displacements over this window [s].
        speed_skip_start_s: speeds in the first part of a motion are ignored (acceleration) [s].
        speed_skip_end_m: … and within this distance of where the motion ends (deceleration) [m].
        speed_min_samples: a speed clause needs this many samples in its zone to be judged; with
            fewer (the end effector never entered the zone) it holds vacuously.
        velocity_bands: velocity words → (lo, hi) ratio of the median measured speed in the zone
            to the controller's default speed ``ee_speed``.
        drawer_closed_m: a drawer is closed when open less than this [m].
        line_band_m: "along the [line]": the block centre stays this close to the line's axis [m].
        line_progress_m: … and advances at least this far along it [m].
        push_min_displacement_m: "push the [obj]": the block moves at least this far [m].
        obstacle_clearance_m: "staying away from [obstacle]": pushed block ↔ obstacle centre
            distance at least this at all times [m] (4 cm between the blocks' faces).
        moved_max_m: blocks the task does not ask to move (obstacles, references) may move at
            most this far [m].
        held_distance_m: a grasped block's centre is within this distance of the end effector [m].
        held_opening_m: … and the fingers are between these openings (lo, hi) [m].
        lift_m: a grasped block is lifted at least this far above the table [m].
        hover_radius_m: "hover [h]cm over the [obj]" (multi-step suite): the end effector is
            within this distance of the point [h] cm above the block's top face [m].
        away_m: "move away from the [obj]" (multi-step suite): the end effector is at least this
            far from the block's faces [m].
    """

    corner_radius_m: float = 0.08
    ee_max_height_m: float = 0.15
    rest_height_m: float = 0.04
    above_height_m: tuple[float, float] = (0.01, 0.15)
    above_lateral_m: float = 0.03
    beside_gap_m: tuple[float, float] = (0.0, 0.12)
    beside_lateral_m: float = 0.04
    beside_max_height_m: float = 0.12
    side_slack_m: float = 0.01
    min_dist_slack_m: float = 0.005
    speed_window_s: float = 0.1
    speed_skip_start_s: float = 0.2
    speed_skip_end_m: float = 0.03
    speed_min_samples: int = 5
    velocity_bands: Mapping[str, tuple[float, float]] = field(default_factory=_default_bands)
    drawer_closed_m: float = 0.02
    line_band_m: float = 0.04
    line_progress_m: float = 0.14
    push_min_displacement_m: float = 0.05
    obstacle_clearance_m: float = 0.09
    moved_max_m: float = 0.03
    held_distance_m: float = 0.05
    held_opening_m: tuple[float, float] = (0.035, 0.075)
    lift_m: float = 0.05
    hover_radius_m: float = 0.03
    away_m: float = 0.10

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "velocity_bands":
                for word, band in dict(value).items():
                    self._check_range(f"velocity_bands[{word!r}]", band)
            elif isinstance(value, tuple):
                self._check_range(f.name, value)
            elif f.name == "speed_min_samples":
                if not isinstance(value, int) or value < 1:
                    raise ConfigError(f"Tolerances.speed_min_samples must be an int >= 1; got "
                                      f"{value!r}")
            elif not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise ConfigError(f"Tolerances.{f.name} must be a positive number; got {value!r}")

    @staticmethod
    def _check_range(name: str, band: Any) -> None:
        ok = (isinstance(band, tuple) and len(band) == 2
              and all(isinstance(v, int | float) for v in band) and 0 <= band[0] < band[1])
        if not ok:
            raise ConfigError(f"Tolerances.{name} must be (lo, hi) with 0 <= lo < hi; got {band!r}")

    def velocity_band(self, word: str) -> tuple[float, float]:
        """The speed-ratio band of a velocity word; raises ConfigError listing the known words."""
        if word not in self.velocity_bands:
            raise ConfigError(f"unknown velocity {word!r}; known: {', '.join(self.velocity_bands)}")
        return self.velocity_bands[word]

    def rows(self) -> list[tuple[str, str]]:
        """(name, value) of every tolerance, for reports."""
        out = []
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "velocity_bands":
                for word, (lo, hi) in dict(value).items():
                    out.append((f"speed ratio for '{word}'", f"[{lo:g}, {hi:g}]"))
            else:
                out.append((f.name, str(value)))
        return out
