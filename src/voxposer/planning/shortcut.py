"""Any-angle shortening of a grid path: straight segments where they cost no more.

The global search moves between neighbouring voxels in 26 directions, so among paths of equal
cost it may return one that bends where a straight line would do: a climb of 10 cm taken as a
run of (−1, +1, +1) moves turns the path 45° away from its heading, and the waypoints then
pass several centimetres beside the straight way (dev records, "staying on the top of": the
hand passed 2.3 cm beside the block it was to pass over, 10 cm above it, on a path the search
found optimal). :func:`shortcut` replaces runs of the path by the straight segment between
their ends when that segment keeps clear of obstacles and its cost, measured on the same cost
map the same way, is no more than the run's: the shortened path never costs more than the one
found. A segment must keep the clearance the search's moves keep: a cube one voxel wide swept
along it touches no obstacle voxel (a path through voxel centres keeps half a voxel from every
obstacle voxel), and the planner keeps the shortened path only when the workspace grid's own
collision check finds it free too.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.planning.search_kernel import near_blocked

#: Samples per voxel along a segment when its cost and obstacles are read.
SAMPLES_PER_VOXEL = 2


def shortcut(
    points: NDArray[np.float64],
    grid: VoxelGrid,
    cost: NDArray[np.floating],
    obstacles: NDArray[np.bool_],
    length_weight: float,
    avoidance: NDArray[np.floating] | None = None,
) -> NDArray[np.float64]:
    """The vertices of ``points`` kept by greedy shortening (module docs), shape (M, 3), M <= N.

    From each kept vertex the farthest later vertex reachable by a straight segment is kept
    next: one along which a voxel-wide cube touches no obstacle voxel (the first vertex's own
    voxel aside: a start may sit in one) and that costs no more than the path between them.
    Costs follow the search's: each sample step of length ``ds`` [voxels] pays
    ``ds * (length_weight + cost)`` at the sample's voxel.

    Args:
        points: the path's vertices [m], shape (N, 3), first the start, last the target.
        grid: the grid ``cost`` and ``obstacles`` are on.
        cost: per-voxel cost, shape ``grid.shape``.
        obstacles: voxels no segment may enter, shape ``grid.shape``.
        length_weight: cost per voxel of length (the search's).
        avoidance: the cost's avoidance term, shape ``grid.shape``, or None: given, a segment
            is kept only where it comes no nearer what is avoided than the run it replaces
            (its largest avoidance value at most the run's): an equal total cost may otherwise
            be a shorter way closer to the avoided object.
    """
    n = len(points)
    if n <= 2:
        return points
    # work in voxel coordinates: a voxel's index is the floor of the point's coordinate
    vox = (np.asarray(points, dtype=np.float64) - grid.bounds_min) / grid.resolution
    limit = np.asarray(grid.shape) - 1
    near = near_blocked(np.asarray(obstacles, dtype=bool))
    price, _, worst = _prices(vox[:-1], vox[1:], cost, obstacles, near, avoidance,
                              length_weight, limit)
    along = np.concatenate([[0.0], np.cumsum(price)])
    kept, i = [0], 0
    while i < n - 1:
        ends = np.arange(i + 1, n)
        price, blocked, nearest = _prices(np.repeat(vox[i:i + 1], len(ends), axis=0), vox[ends],
                                          cost, obstacles, near, avoidance, length_weight,
                                          limit)
        fine = ~blocked & (price <= along[ends] - along[i] + 1e-9) \
            & (nearest <= np.maximum.accumulate(worst[i:]) + 1e-9)
        fine[0] = True  # the path's own next vertex
        i = int(ends[np.flatnonzero(fine)[-1]])
        kept.append(i)
    return points[kept]


def _prices(a: NDArray[np.float64], b: NDArray[np.float64], cost: NDArray[np.floating],
            obstacles: NDArray[np.bool_], near: NDArray[np.bool_],
            avoid: NDArray[np.floating] | None, length_weight: float, limit: NDArray[np.int64]
            ) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.float64]]:
    """For K straight segments a → b (voxel coordinates, shapes (K, 3)): their costs, shape
    (K,), whether a voxel-sized cube swept along each touches an obstacle voxel other than
    its first point's, shape (K,), and the largest ``avoid`` value each passes, shape (K,)
    (zeros without ``avoid``). Read every 1 / ``SAMPLES_PER_VOXEL`` voxel; the cube's corners
    find every voxel it touches, and cubes half a voxel apart cover the swept volume.
    Only samples in a voxel ``near`` an obstacle (one of its 26 neighbours or itself blocked)
    can touch one, so only their corners are read."""
    length = np.linalg.norm(b - a, axis=1)  # [voxels]
    steps = np.maximum(np.ceil(length * SAMPLES_PER_VOXEL).astype(np.int64), 1)
    t = np.arange(1, int(steps.max()) + 1)[None, :] / steps[:, None]  # (K, S)
    valid = t <= 1.0 + 1e-12
    samples = a[:, None, :] + np.minimum(t, 1.0)[..., None] * (b - a)[:, None, :]
    idx = np.clip(np.floor(samples).astype(np.int64), 0, limit)
    at = (idx[..., 0], idx[..., 1], idx[..., 2])
    price = np.sum(np.where(valid, length_weight + cost[at], 0.0), axis=1) * length / steps
    nearest = np.zeros(len(a)) if avoid is None else np.max(np.where(valid, avoid[at], 0.0),
                                                            axis=1)
    seg, col = np.nonzero(valid & near[at])  # the samples whose cube may touch an obstacle
    first = np.clip(np.floor(a).astype(np.int64), 0, limit)[seg][:, None, :]
    corners = np.clip(np.floor(samples[seg, col][:, None, :] + _CORNERS).astype(np.int64),
                      0, limit)
    hit = np.any(obstacles[corners[..., 0], corners[..., 1], corners[..., 2]]
                 & np.any(corners != first, axis=2), axis=1)
    blocked = np.zeros(len(a), dtype=bool)
    blocked[seg[hit]] = True
    return price, blocked, nearest


#: The corners of a cube a hair smaller than a voxel around a point (voxel units), shape (8, 3):
#: a path through voxel centres touches only its own voxels and, on a diagonal move, the
#: voxels of the corner it turns (which the search requires free).
_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)],
                    dtype=np.float64) * (0.5 - 1e-6)


__all__ = ["SAMPLES_PER_VOXEL", "shortcut"]
