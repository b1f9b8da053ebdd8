"""``detect(name)``: an object's centre, box, occupancy and normal from a labelled point cloud.

In simulation the labels are ground-truth segmentation (as in the paper's simulated setup); all
geometry comes from the fused point cloud, not from the simulator's body poses.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Final

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ObjectNotVisibleError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.field_mapping import FieldMapping
from voxposer.perception.point_cloud import PointCloud

_KEYS: Final = ("name", "position", "aabb", "occupancy", "normal", "points", "normals")


@dataclass(frozen=True, eq=False)
class DetectedObject(FieldMapping):
    """An object found in the point cloud. Also readable like a dict: ``obj["position"]``.

    Attributes:
        name: canonical object name ("blue block").
        position: centre of the object's axis-aligned box [m], shape (3,).
        aabb: axis-aligned box [m], shape (2, 3): rows min and max.
        occupancy: voxels holding at least one of its points, shape ``grid.shape``, bool.
        normal: mean unit surface normal of its points, shape (3,) (zeros if undefined).
        points: its points [m], shape (N, 3).
        normals: per-point normals, shape (N, 3).
    """

    keys_: ClassVar[tuple[str, ...]] = _KEYS
    noun: ClassVar[str] = "a detected object"

    name: str
    position: NDArray[np.float64]
    aabb: NDArray[np.float64]
    occupancy: NDArray[np.bool_]
    normal: NDArray[np.float64]
    points: NDArray[np.float64]
    normals: NDArray[np.float64]


    def __repr__(self) -> str:
        return (f"DetectedObject(name={self.name!r}, position={np.round(self.position, 3).tolist()}, "
                f"points={len(self.points)})")


def _frozen(arr: NDArray[Any]) -> NDArray[Any]:
    arr.flags.writeable = False
    return arr


def detect_in_cloud(cloud: PointCloud, labels: NDArray[np.int32], name: str,
                    grid: VoxelGrid, *, horizontal_normal: bool = False) -> DetectedObject:
    """Gather the points whose label is in ``labels`` into a :class:`DetectedObject`.

    The normal is the mean of the points' unit normals. With ``horizontal_normal`` (a part
    mounted on a vertical face: a drawer, a handle) only the points facing sideways (|n_z| < 0.5)
    count and the result is horizontal: cameras above the table mostly see such a part's top, which
    would otherwise tilt its normal upward (a handle's by ~35–50°).

    Raises:
        ObjectNotVisibleError: when no point carries one of the labels.
    """
    mask = np.isin(cloud.labels, labels)
    if not np.any(mask):
        raise ObjectNotVisibleError(f"the {name} is in the scene but no camera sees it")
    return object_from_points(name, cloud.points[mask], cloud.normals[mask], grid,
                              horizontal_normal=horizontal_normal)


def object_from_points(name: str, pts: NDArray[np.float64], nrm: NDArray[np.float64],
                       grid: VoxelGrid, *, horizontal_normal: bool = False) -> DetectedObject:
    """The :class:`DetectedObject` made of ``pts`` (N ≥ 1, 3) [m] with normals ``nrm`` (N, 3)
    (see :func:`detect_in_cloud` for the normal)."""
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    valid = np.linalg.norm(nrm, axis=1) > 0.5
    if horizontal_normal and np.any(valid & (np.abs(nrm[:, 2]) < 0.5)):
        valid &= np.abs(nrm[:, 2]) < 0.5
    mean = nrm[valid].mean(axis=0) if np.any(valid) else np.zeros(3)
    if horizontal_normal:
        mean[2] = 0.0
    length = float(np.linalg.norm(mean))
    normal = mean / length if length > 1e-9 else np.zeros(3)
    return DetectedObject(
        name=name,
        position=_frozen((lo + hi) / 2.0),
        aabb=_frozen(np.stack([lo, hi])),
        occupancy=_frozen(grid.points_to_occupancy(pts)),
        normal=_frozen(normal),
        points=_frozen(pts),
        normals=_frozen(nrm),
    )
