"""The one place where table words ("back left corner", "right side") become geometry.

A base module (like :mod:`voxposer.errors`): the simulator, the programs' API and the
benchmark all import it, and it imports none of them.

Both sides of the benchmark read these definitions: the programs' API (``point_on(table, ...)``,
``region_mask(table, ...)`` in :mod:`voxposer.lmp.api`) aims at them, and the benchmark's checks
(:mod:`voxposer.bench`) measure against them, so a correct program lands inside what is checked.

World frame (metres): front = +x, back = −x, right = +y, left = −y; the table top spans
x ∈ [−0.70, 0.30], y ∈ [−0.50, 0.50] and the robot base stands at (−0.60, 0). The true table
corners are out of reach (≈ 0.75 m from the base), so every place is defined on the *reachable
table* x ∈ [−0.50, 0.13], y ∈ [−0.38, 0.38]:

* a **corner** is a point inset ≈ 8–12 cm from the reachable table's corner; being "at" it means
  a horizontal distance below ``Tolerances.corner_radius_m``;
* a **side** is a band of the table along that edge (half-plane): right y ≥ 0.15, left y ≤ −0.15,
  front x ≥ −0.08, back x ≤ −0.31. Each side also has a target point well inside it.

The back side's point (−0.38, 0) is nearer the table's middle than the back corners' x: straight
in front of the base the Panda cannot hold its hand top-down between x ≈ −0.40 and the base at
heights ≈ 0.18–0.30 m (the elbow is fully folded, joint 4 at its limit), so a place at x = −0.42
could only be reached from below that pocket and a carry or a descent from the ready pose
stalled on its boundary. Band and point keep the same 7 cm margin as before.

A place's **region** (:meth:`Place.region`) is its side band, or for a corner the intersection of
the two side bands that meet there (the back left corner region is back ∩ left).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer import tabletop
from voxposer.errors import ConfigError

#: Table top extent [m] (:mod:`voxposer.tabletop`), used to express places as fractions.
TABLE_MIN: Final = tabletop.TABLE_MIN
TABLE_MAX: Final = tabletop.TABLE_MAX


@dataclass(frozen=True)
class Place:
    """A named place on the table.

    Attributes:
        name: the words of the instruction ("back left corner of the table").
        kind: "corner" (a point) or "side" (a half-plane band).
        point: target (x, y) [m] a correct program aims for.
        axis: for sides, 0 (x) or 1 (y): the coordinate the half-plane bounds.
        sign: for sides, +1 when the side is ``coord >= bound``, −1 when ``coord <= bound``.
        bound: for sides, the half-plane's boundary [m].
    """

    name: str
    kind: Literal["corner", "side"]
    point: tuple[float, float]
    axis: int = 0
    sign: int = 1
    bound: float = 0.0

    def margin(self, xy: ArrayLike, corner_radius: float) -> NDArray[np.float64]:
        """Signed distance [m] inside the place (> 0 inside) for points ``xy``, shape (..., 2)."""
        p = np.asarray(xy, dtype=np.float64)[..., :2]
        if self.kind == "corner":
            return corner_radius - np.linalg.norm(p - np.asarray(self.point), axis=-1)
        return self.sign * (p[..., self.axis] - self.bound)

    def contains(self, xy: ArrayLike, corner_radius: float) -> NDArray[np.bool_]:
        """Whether points ``xy`` (shape (..., 2) or (..., 3), metres) are in the place."""
        return self.margin(xy, corner_radius) >= 0.0

    def region(self, xy: ArrayLike) -> NDArray[np.bool_]:
        """Whether points ``xy`` (shape (..., 2+), metres) lie in the place's region: its band for
        a side, the two adjoining side bands' intersection for a corner."""
        if self.kind == "side":
            return self.contains(xy, 0.0)
        sides = [p for p in PLACES.values() if p.kind == "side" and p.words.split()[0] in
                 self.words.split()]
        return np.logical_and.reduce([s.contains(xy, 0.0) for s in sides])

    @property
    def words(self) -> str:
        """The place without "of the table" ("back left corner")."""
        return self.name.removesuffix(" of the table")


def _side(name: str, axis: int, sign: int, bound: float, point: tuple[float, float]) -> Place:
    return Place(name, "side", point, axis, sign, bound)


#: Every [pos] / [region] value of App. A.5.
PLACES: Final[dict[str, Place]] = {
    p.name: p
    for p in (
        Place("back left corner of the table", "corner", (-0.42, -0.28)),
        Place("back right corner of the table", "corner", (-0.42, 0.28)),
        Place("front left corner of the table", "corner", (0.04, -0.28)),
        Place("front right corner of the table", "corner", (0.04, 0.28)),
        _side("right side of the table", 1, +1, 0.15, (-0.20, 0.28)),
        _side("left side of the table", 1, -1, -0.15, (-0.20, -0.28)),
        _side("front side of the table", 0, +1, -0.08, (0.05, 0.0)),
        _side("back side of the table", 0, -1, -0.31, (-0.38, 0.0)),
    )
}


def get_place(name: str) -> Place:
    """The place called ``name``; raises ConfigError listing the known places."""
    if name not in PLACES:
        raise ConfigError(f"unknown place {name!r}; places are: {', '.join(PLACES)}")
    return PLACES[name]


def place_for_signs(signs: dict[int, int]) -> Place | None:
    """The table place named by horizontal directions ``{axis: sign}`` (axis 0 = x: +1 front,
    −1 back; axis 1 = y: +1 right, −1 left), e.g. ``{0: -1, 1: -1}`` → back left corner;
    None when no horizontal direction is given. A vertical entry (axis 2) is ignored."""
    words = []
    if signs.get(0):
        words.append("front" if signs[0] > 0 else "back")
    if signs.get(1):
        words.append("right" if signs[1] > 0 else "left")
    if not words:
        return None
    kind = "corner" if len(words) == 2 else "side"
    return PLACES[f"{' '.join(words)} {kind} of the table"]
