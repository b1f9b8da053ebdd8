"""Connected 3-D clusters of a point set: its occupied voxels, labelled by scipy.ndimage.

Points from several cameras that fall into the same or touching voxels join one cluster, so
clustering the fused cloud of all views is also how views are associated: two cameras' pixels
of one object overlap in 3-D.
"""

from __future__ import annotations

from typing import Final, NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

#: Default voxel edge [m]: points closer than about this join one cluster.
VOXEL_M: Final = 0.01


class Clusters(NamedTuple):
    """Cluster membership of a point set.

    Attributes:
        labels: cluster index of each point, shape (N,), int64, in 0 … n_clusters − 1, ordered by
            size (0 holds the most points).
        sizes: points per cluster, shape (n_clusters,), descending.
    """

    labels: NDArray[np.int64]
    sizes: NDArray[np.int64]

    @property
    def n_clusters(self) -> int:
        """Number of clusters."""
        return len(self.sizes)


def cluster_points(points: NDArray[np.float64], voxel_m: float = VOXEL_M) -> Clusters:
    """Connected components (26-connected voxels of edge ``voxel_m`` [m]) of ``points`` [m],
    shape (N, 3)."""
    if len(points) == 0:
        return Clusters(np.zeros(0, np.int64), np.zeros(0, np.int64))
    cells = np.floor((points - points.min(axis=0)) / voxel_m).astype(np.int64)
    occupied = np.zeros(tuple(cells.max(axis=0) + 1), dtype=bool)
    occupied[tuple(cells.T)] = True
    components, _ = ndimage.label(occupied, structure=np.ones((3, 3, 3), dtype=bool))
    raw = components[tuple(cells.T)] - 1
    sizes = np.bincount(raw)
    order = np.argsort(-sizes, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return Clusters(rank[raw].astype(np.int64), sizes[order].astype(np.int64))


def box_gap(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Largest per-axis gap [m] between the axis-aligned boxes of point sets ``a`` and ``b``
    (shapes (N, 3), (M, 3)); 0 when the boxes overlap."""
    gap = np.maximum(a.min(axis=0) - b.max(axis=0), b.min(axis=0) - a.max(axis=0))
    return float(max(0.0, gap.max()))


__all__ = ["VOXEL_M", "Clusters", "box_gap", "cluster_points"]
