"""An articulated object's state read from its observed points (handle, door, window).

Online dynamics learning observes the object as a robot would: through its cameras. From the
points perception labels as each part:

- the handle's position: the centre of its points' box [m];
- a hinged part's opening angle (a door, a fridge door): the direction of its points' largest
  horizontal spread (the leaf's width), against that direction when closed [rad];
- a lever's press angle: the tilt of its points' principal axis from the horizontal, against
  the tilt when released [rad];
- a sliding part's offset (a window sash): how far its points' centre moved in the horizontal
  plane since the reset [m].

A part hidden at some instant (the gripper in front of the handle) keeps its last estimate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ObjectNotVisibleError
from voxposer.perception.perceiver import Perceiver

#: Fewer points than this and a part is treated as hidden.
MIN_POINTS = 8


@dataclass(frozen=True)
class ArticulationParts:
    """The part names (as perception knows them) whose state is read.

    Attributes:
        handle: the part grasped (its position is observed).
        hinged: a part turning about a vertical hinge (its opening angle), if any.
        sliding: a part sliding in the horizontal plane (its offset), if any.
        lever: a part turning about a horizontal axis (its press angle), if any.
    """

    handle: str
    hinged: str | None = None
    sliding: str | None = None
    lever: str | None = None

    @property
    def names(self) -> tuple[str, ...]:
        """Every part named, without repeats."""
        out: list[str] = []
        for n in (self.handle, self.hinged, self.sliding, self.lever):
            if n is not None and n not in out:
                out.append(n)
        return tuple(out)


def horizontal_direction(points: NDArray[np.float64]) -> float:
    """Angle [rad] in [0, π) of the largest spread of ``points`` (N, 3) in the table plane."""
    xy = points[:, :2] - points[:, :2].mean(axis=0)
    _, _, vt = np.linalg.svd(xy, full_matrices=False)
    v = vt[0]
    return float(math.atan2(v[1], v[0]) % math.pi)


def tilt(points: NDArray[np.float64]) -> float:
    """Angle [rad] in [0, π/2] between the principal axis of ``points`` (N, 3) and the table."""
    centred = points - points.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    return float(math.asin(min(1.0, abs(float(vt[0][2])))))


def _turn(angle: float, reference: float) -> float:
    """Unsigned difference [rad] in [0, π/2] of two undirected angles in [0, π)."""
    d = abs(angle - reference) % math.pi
    return min(d, math.pi - d)


class ArticulationEstimator:
    """Reads :class:`ArticulationParts` states through a perceiver; :meth:`reset` with the
    object closed and the lever released, then :meth:`estimate` at every step."""

    def __init__(self, perceiver: Perceiver, parts: ArticulationParts) -> None:
        self.perceiver = perceiver
        self.parts = parts
        self._ref: dict[str, float | NDArray[np.float64]] = {}
        self._last: dict[str, float | NDArray[np.float64]] = {}

    def _points(self, name: str) -> NDArray[np.float64] | None:
        try:
            pts = np.asarray(self.perceiver.detect(name).points, dtype=np.float64)
        except ObjectNotVisibleError:
            return None
        return pts if len(pts) >= MIN_POINTS else None

    def _measure(self) -> dict[str, float | NDArray[np.float64]]:
        out: dict[str, float | NDArray[np.float64]] = {}
        p = self.parts
        handle = self._points(p.handle)
        if handle is not None:
            out["handle_position"] = 0.5 * (handle.min(axis=0) + handle.max(axis=0))
        if p.hinged is not None and (leaf := self._points(p.hinged)) is not None:
            out["hinge_direction"] = horizontal_direction(leaf)
        if p.lever is not None and (lever := self._points(p.lever)) is not None:
            out["lever_tilt"] = tilt(lever)
        if p.sliding is not None and (sash := self._points(p.sliding)) is not None:
            out["sliding_centre"] = sash.mean(axis=0)
        return out

    def reset(self) -> None:
        """Take the references from the current observation.

        Raises:
            ObjectNotVisibleError: a part is not seen at all at the reset.
        """
        measured = self._measure()
        needed = ["handle_position"]
        needed += ["hinge_direction"] * (self.parts.hinged is not None)
        needed += ["lever_tilt"] * (self.parts.lever is not None)
        needed += ["sliding_centre"] * (self.parts.sliding is not None)
        missing = [k for k in needed if k not in measured]
        if missing:
            raise ObjectNotVisibleError(
                f"cannot read the object's state at the reset: {', '.join(missing)} not seen")
        self._ref = measured
        self._last = dict(measured)

    def estimate(self) -> dict[str, NDArray[np.float64] | float]:
        """The state now: ``handle_position`` [m] (3,), and as the parts allow ``door_angle``,
        ``handle_angle`` [rad] and ``window_offset`` [m]."""
        self._last.update(self._measure())
        last, ref = self._last, self._ref
        out: dict[str, NDArray[np.float64] | float] = {
            "handle_position": np.asarray(last["handle_position"], dtype=np.float64)}
        if "hinge_direction" in ref:
            out["door_angle"] = _turn(float(last["hinge_direction"]),
                                      float(ref["hinge_direction"]))
        if "lever_tilt" in ref:
            out["handle_angle"] = max(0.0, float(last["lever_tilt"]) - float(ref["lever_tilt"]))
        if "sliding_centre" in ref:
            shift = np.asarray(last["sliding_centre"]) - np.asarray(ref["sliding_centre"])
            out["window_offset"] = float(np.linalg.norm(shift[:2]))
        return out


__all__ = ["MIN_POINTS", "ArticulationEstimator", "ArticulationParts", "horizontal_direction",
           "tilt"]
