"""Objects as the generated code sees them: voxel coordinates on the workspace grid."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Final

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.field_mapping import FieldMapping

_KEYS: Final = ("name", "position", "aabb", "occupancy", "normal", "position_world", "aabb_world")


def detection_field(det: Any, key: str) -> Any:
    """Field ``key`` of a perception result (attribute or item access)."""
    return det[key] if isinstance(det, Mapping) else getattr(det, key)


@dataclass(frozen=True, eq=False)
class ObjectView(FieldMapping):
    """A detected object in voxel coordinates; also readable like a dict (``obj["position"]``).

    Every detection is a fresh object: generated code may change its small arrays in place
    (``obj.position[2] += 5``) without touching perception; ``occupancy`` is read-only.

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
            return detection_field(det, key)

        pos = np.array(field("position"), float).reshape(3)
        aabb = np.array(field("aabb"), float).reshape(2, 3)
        normal = np.array(field("normal"), float).reshape(3)
        occ = np.asarray(field("occupancy"), bool)
        occ.flags.writeable = False  # large and shared with perception; the rest are copies
        return cls(name, grid.world_to_voxel(pos, clip=True), grid.world_to_voxel(aabb, clip=True),
                   occ, normal, pos, aabb)


    def __repr__(self) -> str:
        return f"ObjectView({self.name!r}, position={self.position.tolist()})"
