"""Objects as the generated code sees them (voxel coordinates) and lenient name matching."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Final

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import UnknownObjectError
from voxposer.perception.field_mapping import FieldMapping
from voxposer.valuemaps.grid import VoxelGrid

_KEYS: Final = ("name", "position", "aabb", "occupancy", "normal", "position_world", "aabb_world")
#: Word-level synonyms applied before matching names.
_SYNONYMS: Final = {
    "grey": "gray", "cube": "block", "box": "block", "end effector": "gripper",
    "ee": "gripper", "hand": "gripper", "robot hand": "gripper", "topmost": "top",
    "bottommost": "bottom", "second to the top": "middle", "second to the bottom": "middle",
    "lowest": "bottom", "highest": "top", "desk": "table", "tabletop": "table",
    "table top": "table", "cupboard": "cabinet",
}


def normalize_name(name: str) -> str:
    """Lower case, single spaces, no article/possessive, synonyms replaced."""
    key = re.sub(r"[\s_]+", " ", str(name)).strip().lower()
    key = re.sub(r"^(the|a|an) ", "", key).replace("'s", "")
    for word, canon in _SYNONYMS.items():
        key = re.sub(rf"\b{re.escape(word)}\b", canon, key)
    return key


def match_name(query: str, names: Sequence[str]) -> str:
    """The scene name ``query`` refers to, by whole words.

    Exact match first; then the most specific name whose words all appear in the query
    ("handle of the top drawer" → "top drawer handle"); then the shortest name holding every
    word of the query ("blue" → "blue block" when there is no "blue line").

    Raises:
        UnknownObjectError: no (or no unique) match; the message lists the scene's names.
    """
    key = normalize_name(query)
    canon = {normalize_name(n): n for n in names}
    if key in canon:
        return canon[key]
    words = set(key.split())
    inside = [(len(c.split()), n) for c, n in canon.items() if set(c.split()) <= words]
    if inside:
        inside.sort(reverse=True)
        if len(inside) == 1 or inside[0][0] > inside[1][0]:
            return inside[0][1]
    holding = sorted((len(c.split()), n) for c, n in canon.items() if words <= set(c.split()))
    if len(holding) == 1 or (len(holding) > 1 and holding[0][0] < holding[1][0]):
        return holding[0][1]
    raise UnknownObjectError(str(query), names)


@dataclass(frozen=True, eq=False)
class ObjectView(FieldMapping):
    """A detected object in voxel coordinates; also readable like a dict (``obj["position"]``).

    Attributes:
        name: the scene's name for it.
        position: voxel index of its centre, int, shape (3,).
        aabb: voxel indices of its box, int, shape (2, 3): rows min and max corner.
        occupancy: voxels it occupies, bool, shape ``grid.shape``.
        normal: mean outward surface normal (world frame, unit), shape (3,).
        position_world: centre [m], shape (3,).
        aabb_world: box [m], shape (2, 3).
    """

    keys_: ClassVar[tuple[str, ...]] = _KEYS
    noun: ClassVar[str] = "an object"

    name: str
    position: NDArray[np.int64]
    aabb: NDArray[np.int64]
    occupancy: NDArray[np.bool_]
    normal: NDArray[np.float64]
    position_world: NDArray[np.float64]
    aabb_world: NDArray[np.float64]

    @classmethod
    def from_detection(cls, name: str, det: Any, grid: VoxelGrid) -> ObjectView:
        """Build from a perception result (world frame, attribute or item access)."""

        def field(key: str) -> Any:
            return det[key] if isinstance(det, Mapping) else getattr(det, key)

        pos = np.asarray(field("position"), float).reshape(3)
        aabb = np.asarray(field("aabb"), float).reshape(2, 3)
        normal = np.asarray(field("normal"), float).reshape(3)
        occ = np.asarray(field("occupancy"), bool)
        arrays = (grid.world_to_voxel(pos, clip=True), grid.world_to_voxel(aabb, clip=True),
                  occ, normal, pos, aabb)
        for arr in arrays:
            arr.flags.writeable = False
        return cls(name, *arrays)


    def __repr__(self) -> str:
        return f"ObjectView({self.name!r}, position={self.position.tolist()})"
