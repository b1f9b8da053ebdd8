"""Post-conditions over the path a sub-task executed: ``away``, ``passed_on``, ``speed``,
``along``, and the distance it ends at, ``far`` (a mixin of :class:`voxposer.lmp.intent.IntentChecks`, which records the paths).

Distances are in centimetres as the instruction states them. The paths are the end effector's
``trace`` and the moved entity's ``entity_path`` of every ``execute`` call of the last sub-task
(:meth:`~voxposer.lmp.intent.IntentChecks.add_execution`).
"""

from __future__ import annotations

from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.intent_conditions import Condition, call_text
from voxposer.lmp.intent_paths import (
    SIDE_SLACK_M,
    box_gap,
    compact_gap,
    is_compact,
    line_progress,
    motion_speeds,
    side_pass,
    speed_band,
)
from voxposer.lmp.sides import parse_side

#: default distance [cm] within which something is "near" another.
NEAR_CM: Final = 5.0
#: default distance [cm] between the faces of two things that "stayed away" from each other
#: (the benchmark's "staying away from [obstacle]" asks 4 cm between the blocks' faces).
AWAY_CM: Final = 4.0
#: default distance [cm] from an object's faces of a thing that "moved away from" it (the
#: benchmark's multi-step "move away from it" asks 10 cm).
FAR_CM: Final = 10.0
#: how much [cm] a measured distance may fall short of the one asked and still count: half a
#: voxel of the perceived boxes (the benchmark's "at least [dist]cm" allows the same 0.5 cm).
DISTANCE_SLACK_CM: Final = 0.5
#: "along a line": the pushed object's centre within this [cm] of the line's axis.
LINE_BAND_CM: Final = 4.0


class PathConditions:
    """The path-based helpers; the class using it keeps the paths and resolves names."""

    api: LMPAPI
    ee_speed: float | None
    _paths: dict[str, list[NDArray[np.float64]]]
    _timed: list[tuple[NDArray[np.float64], NDArray[np.float64]]]
    _start_half: dict[str, NDArray[np.float64]]
    _start_box: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]]

    def _name(self, obj: Any) -> str:
        raise NotImplementedError

    def _centre(self, name: str) -> NDArray[np.float64]:
        raise NotImplementedError

    def _aabb(self, name: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        raise NotImplementedError

    def away(self, obj: str, target: str, cm: float = AWAY_CM) -> Condition:
        """During the last sub-task ``obj`` (its path when the executor moved it, else where
        it is now) stayed at least ``cm`` [cm] from ``target``'s box — where it is now and
        where it was when the sub-task began (an obstacle pushed aside): between their faces
        for an object, from the end effector's point for the gripper (less
        :data:`DISTANCE_SLACK_CM`: a point against perceived faces); between two compact
        objects (blocks) horizontally by their footprints' inscribed circles
        (:func:`~voxposer.lmp.intent_paths.compact_gap`, from perceived centres: no slack),
        whatever either's turn."""
        name, other = self._name(obj), self._name(target)
        paths = self._paths.get(name, [])
        points = np.concatenate(paths) if paths else self._centre(name)[None]
        boxes = [self._aabb(other)]
        if other in self._start_box:
            boxes.append(self._start_box[other])
        slack = DISTANCE_SLACK_CM
        if name == "gripper":
            gaps = np.min([box_gap(points, *box) for box in boxes], axis=0)
        else:
            lo, hi = self._aabb(name)
            half = self._start_half.get(name, (hi - lo) / 2.0)
            compact = (is_compact(lo, hi) or is_compact(-half, half)) \
                and all(is_compact(*box) for box in boxes)
            gaps = np.min([compact_gap(points, half, *box) if compact
                           else box_gap(points, *box, half) for box in boxes], axis=0)
            slack = 0.0 if compact else DISTANCE_SLACK_CM
        dist = 100.0 * float(gaps.min())
        return Condition(call_text("away", obj, target, cm=cm), dist >= cm - slack,
                         f"closest {dist:.1f} cm to the {other} over {len(points)} points")

    def far(self, obj: str, target: str, cm: float = FAR_CM) -> Condition:
        """``obj`` (its centre, or the end effector) ends at least ``cm`` [cm] from
        ``target``'s box ("move away from it": where the path starts does not count, unlike
        :meth:`away`), less :data:`DISTANCE_SLACK_CM`."""
        name, other = self._name(obj), self._name(target)
        dist = 100.0 * float(box_gap(self._centre(name)[None], *self._aabb(other)).min())
        return Condition(call_text("far", obj, target, cm=cm), dist >= cm - DISTANCE_SLACK_CM,
                         f"the {name} ends {dist:.1f} cm from the {other}")

    def passed_on(self, obj: str, target: str, side: str) -> Condition:
        """While ``obj``'s path in the last sub-task was level with ``target`` (passing it), it
        stayed on its ``side`` ("left side", "top": over it) — beyond that face, ±1 cm."""
        name, other = self._name(obj), self._name(target)
        text = call_text("passed_on", obj, target, side)
        paths = self._paths.get(name, [])
        points = np.concatenate(paths) if paths else self._centre(name)[None]
        passed = side_pass(points, *self._aabb(other), parse_side(side, name=other))
        if passed.level == 0:
            return Condition(text, False, f"never passed the {other}")
        held = bool(passed.margin >= -SIDE_SLACK_M)
        word = "beyond" if passed.margin >= 0 else "across"
        return Condition(text, held, f"passed the {other} {abs(passed.margin) * 100:.1f} cm "
                                     f"{word} its {side} face at worst ({passed.level} points)")

    def speed(self, obj: str, scale: float, near: str | None = None, cm: float = NEAR_CM,
              inside: str | None = None, side: str | None = None) -> Condition:
        """In the last sub-task the end effector (``obj``: "gripper", or what it carries) moved
        at about ``scale`` times its default speed (the median, in the band of
        :func:`~voxposer.lmp.intent_paths.speed_band`: ±1.6x, a speed-up at least partly), counting
        only where it was within ``cm`` [cm] of ``near``'s box, or over the ``inside`` part
        of the table ("back side"; ``side`` is another name for it), when given."""
        if side is not None and inside is not None and side != inside:
            raise ConfigError(f"speed(): inside={inside!r} and side={side!r} name two table "
                              "parts; give one")
        inside = inside if inside is not None else side
        text = call_text("speed", obj, scale, near=near, cm=cm if near else None, inside=inside)
        if self.ee_speed is None:
            raise ConfigError("the robot's default speed is unknown here")
        parts = [motion_speeds(path, times) for path, times in self._timed]
        speeds = np.concatenate([p[0] for p in parts]) if parts else np.zeros(0)
        where = np.concatenate([p[1] for p in parts]) if parts else np.zeros((0, 3))
        zone = ""
        if near is not None:
            other = self._name(near)
            close = box_gap(where, *self._aabb(other)) <= cm / 100.0
            speeds, zone = speeds[close], f" within {cm:g} cm of the {other}"
        if inside is not None:
            over = self._over_table(where, inside)
            speeds, zone = speeds[over], zone + f" over the {inside}"
        if len(speeds) < 5:
            return Condition(text, False, f"hardly moved{zone} ({len(speeds)} samples)")
        ratio = float(np.median(speeds)) / self.ee_speed
        lo, hi = speed_band(float(scale))
        return Condition(text, lo <= ratio <= hi,
                         f"median speed {ratio:.2f}x default{zone} (band [{lo:.2f}, {hi:.4g}])")

    def along(self, obj: str, line: str, cm: float | None = None) -> Condition:
        """During the last sub-task ``obj``'s path went at least ``cm`` [cm] (default: half
        the line's length) along ``line``'s long axis without leaving it (its centre within
        :data:`LINE_BAND_CM` of the axis): a push *along* the line, not onto it."""
        name, other = self._name(obj), self._name(line)
        paths = self._paths.get(name, [])
        points = np.concatenate(paths) if paths else self._centre(name)[None]
        lo, hi = self._aabb(other)
        need = 50.0 * float(np.max((hi - lo)[:2])) if cm is None else float(cm)
        went = 100.0 * line_progress(points, lo, hi, LINE_BAND_CM / 100.0)
        return Condition(call_text("along", obj, line, cm=cm), went >= need,
                         f"went {went:.1f} cm along the {other} (needs {need:.1f})")

    def _over_table(self, points: NDArray[np.float64], where: str) -> NDArray[np.bool_]:
        """Which points (N, 3) [m] lie over the ``where`` part of the table, shape (N,)."""
        grid = self.api.grid
        mask = self.api.region_mask("table", where)
        inside = np.asarray(grid.contains(points), dtype=bool).reshape(-1)
        out = np.zeros(len(points), dtype=bool)
        if np.any(inside):
            i, j, k = np.asarray(grid.world_to_voxel(points[inside])).T
            out[inside] = mask[i, j, k]
        return out



__all__ = ["AWAY_CM", "DISTANCE_SLACK_CM", "FAR_CM", "LINE_BAND_CM", "NEAR_CM", "PathConditions"]
