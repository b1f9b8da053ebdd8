"""The functions generated code may call (paper App. A.3, plus higher-level helpers).

Everything here works in voxel coordinates of the scene's grid (about 1 cm voxels) and is lenient
about its inputs: a voxel may be an int or float array, a list, or an object (its centre); object
names match by synonym and substring. Direction words: front +x, back/behind/rear −x, right +y,
left −y, above/top/over/up +z, below/under/bottom/down −z (also "+x", "-y"…); the words people
use for sides, ends and corners ("the far end", "the near side", "leftmost", "top-left corner",
"nearest to the robot") are read by :mod:`voxposer.lmp.sides`, whose errors list every word.

On the table, corners and sides are the named places of :mod:`voxposer.places` (the places
the robot can reach, which the benchmark checks against): ``point_on(table, "back left corner")``
is that place's point, ``region_mask(table, "right side")`` its band; "half" or an axis token
("-y") splits the table at its centre instead. A point *beside* the table's front/back/left/right
face would lie off the table and outside the workspace, so ``point_beside(table, "front", cm)``
reads as the table's front side, ``cm`` above its surface.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.errors import OutOfWorkspaceError
from voxposer.lmp.object_view import ObjectView
from voxposer.lmp.scene import Scene
from voxposer.lmp.sides import SideError, direction_sign, parse_side, splits_at_centre
from voxposer.perception.names import match_name
from voxposer.places import TABLE_MAX, TABLE_MIN, Place, place_for_signs
from voxposer.valuemaps.maps import ValueMapAPI
from voxposer.valuemaps.voxel_ops import nonzero_voxels

__all__ = ["DEFAULT_OFFSET_CM", "EDGE_INSET", "LMPAPI", "TABLE_MATCH_M", "SideError", "parse_side"]

#: Distance [cm] between an object's face and the point ``point_beside`` returns by default.
DEFAULT_OFFSET_CM: Final = 5.0
#: How far in from an edge ``point_on`` puts "side"/"corner" points (fraction of the extent).
EDGE_INSET: Final = 0.2
#: A detected table whose extent matches the world's table within this [m] uses its named places.
TABLE_MATCH_M: Final = 0.05
#: Axis names ``cm2index`` hands to the grid as they are (an int count along an axis).
NAMED_AXES: Final = frozenset({"x", "y", "z", "+x", "-x", "+y", "-y", "+z", "-z"})


class LMPAPI:
    """The scene-bound API of generated code. :meth:`namespace` lists what the code sees."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.grid = scene.grid
        self.maps = ValueMapAPI(self.grid, ee_quat=lambda: scene.ee_pose()[1],
                                gripper_state=scene.gripper_state)

    # ------------------------------------------------------------------ perception
    def detect(self, name: str) -> ObjectView:
        """The object called ``name`` (synonyms and substrings accepted), in voxel coordinates."""
        if isinstance(name, ObjectView):
            return name
        canonical = match_name(name, self.scene.object_names)
        return ObjectView.from_detection(canonical, self.scene.detect(canonical), self.grid)

    def _obj(self, obj: Any) -> ObjectView:
        return obj if isinstance(obj, ObjectView) else self.detect(str(obj))

    def voxel(self, value: Any, name: str = "voxel") -> NDArray[np.int64]:
        """A valid int voxel index from an index-like value or an object (its centre)."""
        if isinstance(value, ObjectView):
            return value.position.copy()
        if callable(value) and hasattr(value, "position"):
            return np.asarray(value.position, dtype=np.int64)
        return self.grid.check_voxel(np.asarray(value, dtype=np.float64).reshape(-1), name)

    # --------------------------------------------------------------------- helpers
    def point_beside(self, obj: Any, side: str, cm: float = DEFAULT_OFFSET_CM) -> NDArray[np.int64]:
        """Voxel ``cm`` centimetres outside the named face(s) of ``obj``, centred on the others.

        ``side`` is one or more direction words ("left", "top", "back left", "+y"); "center"
        gives the object's centre. Raises OutOfWorkspaceError when the point leaves the grid.
        """
        o = self._obj(obj)
        signs = parse_side(side, surface=o.name == "table", name=o.name)
        place = self._table_place(o, side, signs)
        if place is not None and 2 not in signs:
            return self.point_on(o, side, cm_above=cm)
        lo, hi = o.aabb_world
        point = o.position_world.copy()
        for axis, sign in signs.items():
            face = hi[axis] if sign > 0 else lo[axis]
            point[axis] = face + sign * float(cm) / 100.0
        return self._to_voxel(point, f"point {cm} cm {side} of the {o.name}")

    def point_on(self, obj: Any, where: str = "center", cm_above: float = 0.0) -> NDArray[np.int64]:
        """Voxel on the top surface of ``obj`` at a named part ("back left corner", "left side",
        "center"), raised ``cm_above`` centimetres. Side points lie 20% in from that edge; on the
        table, the named place's point (module docs)."""
        o = self._obj(obj)
        signs = parse_side(where, surface=True, name=o.name)
        lo, hi = o.aabb_world
        point = o.position_world.copy()
        place = self._table_place(o, where, signs)
        for axis, sign in signs.items():
            if axis == 2:
                continue
            span = hi[axis] - lo[axis]
            point[axis] = hi[axis] - EDGE_INSET * span if sign > 0 else lo[axis] + EDGE_INSET * span
        if place is not None:
            point[:2] = place.point
        point[2] = hi[2] + float(cm_above) / 100.0 + 0.5 * self.grid.resolution[2]
        return self._to_voxel(point, f"point on the {where} of the {o.name}")

    def region_mask(self, obj: Any, where: str) -> NDArray[np.bool_]:
        """Bool mask, shape ``grid.shape``: voxels over the named half/quadrant of ``obj``'s
        footprint ("left side", "back left corner"), at every height ("top": above it only). On
        the table, a named place's region (module docs)."""
        o = self._obj(obj)
        signs = parse_side(where, surface=True, name=o.name)
        place = self._table_place(o, where, signs)
        if place is not None:
            nx, ny = self.grid.shape[:2]
            ij = np.stack(np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij"), axis=-1)
            centres = self.grid.voxel_to_world(np.concatenate([ij, np.zeros((nx, ny, 1))], -1))
            mask2d = place.region(centres[..., :2])
            mask = np.repeat(mask2d[:, :, None], self.grid.shape[2], axis=2)
            if signs.get(2, 0) > 0:
                mask[:, :, : o.aabb[1][2] + 1] = False
            elif signs.get(2, 0) < 0:
                mask[:, :, o.position[2] + 1:] = False
            return mask
        lo, hi = o.aabb
        centre = o.position
        mask = np.zeros(self.grid.shape, dtype=bool)
        sl = [slice(lo[0], hi[0] + 1), slice(lo[1], hi[1] + 1), slice(None)]
        for axis, sign in signs.items():
            if axis == 2:
                sl[2] = slice(hi[2] + 1, None) if sign > 0 else slice(0, centre[2] + 1)
            else:
                sl[axis] = slice(centre[axis], hi[axis] + 1) if sign > 0 else slice(lo[axis], centre[axis])
        mask[tuple(sl)] = True
        return mask

    def end_of(self, obj: Any, end: str = "high", cm_in: float = 0.0) -> NDArray[np.int64]:
        """Voxel at an end of ``obj``'s long axis (a line's: the principal axis of its
        footprint, not its box, so a line at a slant keeps it), ``cm_in`` centimetres in from
        that end, at the object's centre height. ``end``: "low" or "high", the end with the
        smaller or larger coordinate along its box's longer horizontal side (x or y)."""
        o = self._obj(obj)
        if end not in ("low", "high"):
            raise SideError(f"end_of(..., end={end!r}): end must be 'low' or 'high'")
        lo, hi = o.aabb_world
        k = 0 if hi[0] - lo[0] >= hi[1] - lo[1] else 1
        cells = nonzero_voxels(o.occupancy)
        xy = self.grid.voxel_to_world(cells)[:, :2] if len(cells) >= 3 else None
        centre = o.position_world[:2] if xy is None else xy.mean(axis=0)
        axis = np.eye(2)[k] if xy is None else np.linalg.svd(xy - centre, full_matrices=False)[2][0]
        axis = axis if axis[k] >= 0 else -axis
        t = (np.array([lo[:2], hi[:2]]) - centre) @ axis if xy is None else (xy - centre) @ axis
        reach = (float(t.max()) if end == "high" else float(t.min()))
        reach -= np.sign(reach) * float(cm_in) / 100.0
        point = np.array([*(centre + reach * axis), o.position_world[2]])
        return self._to_voxel(point, f"the {end} end of the {o.name}")

    def _table_place(self, o: ObjectView, where: str, signs: dict[int, int]) -> Place | None:
        """The named table place ``where`` picks on ``o`` (None: not the table, a "half", an axis
        token, no horizontal word, or a table unlike the world's)."""
        if o.name != "table" or splits_at_centre(where):
            return None
        lo, hi = o.aabb_world
        if max(abs(lo[0] - TABLE_MIN[0]), abs(lo[1] - TABLE_MIN[1]), abs(hi[0] - TABLE_MAX[0]),
               abs(hi[1] - TABLE_MAX[1])) > TABLE_MATCH_M:
            return None
        return place_for_signs(signs)

    def _to_voxel(self, point: NDArray[np.float64], what: str) -> NDArray[np.int64]:
        if not bool(self.grid.contains(point)):
            raise OutOfWorkspaceError(
                f"{what} is at {np.round(point, 3).tolist()} m, outside the workspace "
                f"[{self.grid.bounds_min.tolist()}, {self.grid.bounds_max.tolist()}] m")
        return self.grid.world_to_voxel(point)

    # ------------------------------------------------------------------ paper's API
    def set_voxel_by_radius(self, voxel_map: NDArray, voxel_xyz: Any, radius_cm: float = 0.0,
                            value: ArrayLike = 1.0) -> NDArray:
        """Set voxels within ``radius_cm`` of ``voxel_xyz`` (index or object) to ``value``."""
        return self.maps.set_voxel_by_radius(voxel_map, self.voxel(voxel_xyz, "voxel_xyz"),
                                             radius_cm, value)

    def cm2index(self, cm: float, direction: Any) -> Any:
        """Voxels spanned by ``cm`` centimetres along ``direction`` ("x", "-y", "left", vector)."""
        named = direction_sign(direction) if isinstance(direction, str) else None
        if named is not None and direction.strip().lower() not in NAMED_AXES:
            vec = np.zeros(3)
            vec[named[0]] = named[1]
            return self.grid.cm2index(cm, vec)
        return self.grid.cm2index(cm, direction)

    def index2cm(self, index: float, direction: Any) -> float:
        """Centimetres spanned by ``index`` voxels along ``direction``."""
        return self.grid.index2cm(index, direction)

    def namespace(self) -> dict[str, Callable[..., Any] | Any]:
        """Name → function for generated code (the API reference in the prompts lists them)."""
        m = self.maps
        return {
            "detect": self.detect,
            "point_beside": self.point_beside,
            "point_on": self.point_on,
            "end_of": self.end_of,
            "region_mask": self.region_mask,
            "set_voxel_by_radius": self.set_voxel_by_radius,
            "cm2index": self.cm2index,
            "index2cm": self.index2cm,
            "pointat2quat": m.pointat2quat,
            "get_empty_affordance_map": m.get_empty_affordance_map,
            "get_empty_avoidance_map": m.get_empty_avoidance_map,
            "get_empty_rotation_map": m.get_empty_rotation_map,
            "get_empty_velocity_map": m.get_empty_velocity_map,
            "get_empty_gripper_map": m.get_empty_gripper_map,
            "grid_shape": tuple(self.grid.shape),
            "CLOSED": 1.0,  # gripper map values
            "OPEN": 0.0,
        }
