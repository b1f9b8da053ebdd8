"""Physics queries the success checks share (kept apart from task logic, as in dm_control).

Every function reads ground truth (``world.object_position``…) or an episode :class:`Trace`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from voxposer.bench.config import Tolerances
from voxposer.bench.trace import Trace
from voxposer.envs.layout import MAX_REACH, MIN_REACH
from voxposer.places import Place

#: Robot base (x, y) [m] (``WorldConfig.robot_base``).
BASE_XY = (-0.60, 0.0)
#: Half the block edge [m] (``WorldConfig.block_size / 2``).
BLOCK_HALF = 0.025


def sample_xy(rng: np.random.Generator, lo: tuple[float, float], hi: tuple[float, float],
              ok: Any = None) -> tuple[float, float]:
    """A uniform (x, y) [m] in the box [lo, hi] that a block there can be reached top-down
    (and ``ok(xy)`` accepts); falls back to the box centre after 200 draws."""
    for _ in range(200):
        xy = rng.uniform(lo, hi)
        reach = math.dist(xy, BASE_XY)
        if MIN_REACH + 0.02 <= reach <= MAX_REACH - 0.02 and (ok is None or ok(xy)):
            return float(xy[0]), float(xy[1])
    return (lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2


def ee_at_place(ee: NDArray[np.float64], place: Place, tol: Tolerances) -> tuple[bool, str]:
    """Whether the end effector at ``ee`` [m] is at ``place`` (and low enough)."""
    margin = float(place.margin(ee[:2], tol.corner_radius_m))
    if margin < 0:
        return False, f"end effector {-margin * 100:.1f} cm outside the {place.name}"
    if ee[2] > tol.ee_max_height_m:
        return False, f"end effector {ee[2] * 100:.0f} cm high over the {place.name}"
    return True, f"end effector at the {place.name}"


def block_at_place(pos: NDArray[np.float64], place: Place, tol: Tolerances) -> tuple[bool, str]:
    """Whether a block centred at ``pos`` [m] rests on the table at ``place``."""
    margin = float(place.margin(pos[:2], tol.corner_radius_m))
    if margin < 0:
        return False, f"block {-margin * 100:.1f} cm outside the {place.name}"
    if pos[2] > tol.rest_height_m:
        return False, f"block not resting on the table ({pos[2] * 100:.1f} cm high)"
    return True, f"block at the {place.name}"


def block_distance(points: NDArray[np.float64], centres: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distance [m] from ``points`` to the surface of axis-aligned blocks centred at ``centres``
    (0 inside), both shape (T, 3) → (T,). "Within 5 cm from the block" is measured so: from
    its faces, not its centre."""
    gap = np.maximum(np.abs(np.asarray(points) - np.asarray(centres)) - BLOCK_HALF, 0.0)
    return np.asarray(np.linalg.norm(gap, axis=-1), dtype=np.float64)


def max_displacement(trace: Trace, name: str) -> float:
    """Largest distance [m] of ``name`` from where the trace began."""
    p = trace.objects[name]
    return float(np.max(np.linalg.norm(p - p[0], axis=1))) if len(p) else 0.0


def speed_clause(trace: Trace, zone: NDArray[np.bool_], word: str, ee_speed: float,
                 tol: Tolerances) -> tuple[bool, str, dict[str, float]]:
    """Does the end effector move at ``word`` (e.g. "a quarter of the speed") inside ``zone``?

    ``zone`` marks the trace samples inside the stated region, shape (T,). Samples in the first
    ``speed_skip_start_s`` of motion, within ``speed_skip_end_m`` of the final position, and while
    the gripper is actuating (no motion commanded) are left out. The median speed there over
    ``ee_speed`` must lie in the word's band; with fewer than ``speed_min_samples`` samples the
    clause holds vacuously (reported as such).
    """
    speed = trace.speed(tol.speed_window_s)
    moving = np.linalg.norm(trace.ee - trace.ee[0], axis=1) > 0.01
    start = trace.time[np.argmax(moving)] if np.any(moving) else np.inf
    keep = (zone & np.isfinite(speed) & (trace.time >= start + tol.speed_skip_start_s)
            & (np.linalg.norm(trace.ee - trace.ee[-1], axis=1) > tol.speed_skip_end_m))
    dt = np.diff(trace.time, prepend=trace.time[0])
    keep &= dt < 0.05  # a long gap is a gripper actuation or settling, not commanded motion
    n = int(np.sum(keep))
    if n < tol.speed_min_samples:
        return True, f"never moved inside the zone ({n} samples): speed clause vacuous", {
            "zone_samples": float(n)}
    ratio = float(np.median(speed[keep])) / ee_speed
    lo, hi = tol.velocity_band(word)
    ok = lo <= ratio <= hi
    text = f"median speed {ratio:.2f}x default in the zone ({'in' if ok else 'outside'} " \
           f"[{lo:g}, {hi:g}] for '{word}')"
    return ok, text, {"zone_samples": float(n), "speed_ratio": ratio}


#: velocity words → the speed scale a correct program writes into a velocity map.
VELOCITY_SCALE = {"faster speed": 2.0, "3x speed": 3.0, "slower speed": 0.5,
                  "a quarter of the speed": 0.25}
