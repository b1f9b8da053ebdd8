"""Global lowest-cost path search on a 26-connected voxel grid (A*), and the greedy baseline.

Path cost: each move from voxel ``u`` to a neighbour ``v`` costs
``|v - u| * (length_weight + cost[v])`` (``|v - u|`` is 1, √2 or √3 voxels). Obstacles are
impassable, and a diagonal move may not cut the corner of an obstacle voxel (every voxel in the
box spanned by ``u`` and ``v``, ``u`` aside, must be free), so straight segments between consecutive path
voxels stay in free space.

The heuristic is admissible for cost maps whose affordance term is ``w * d / d_max`` with ``d``
the distance to the nearest target (as :func:`voxposer.valuemaps.cost.compose_cost_map` makes):
from distance ``d`` any path pays at least ``length_weight * d + (w / d_max) * (d - √3)² / 2``.
So A* returns the lowest-cost path, not merely a good one.

The search runs in a numba-compiled kernel (compiled once, cached on disk): a Python-level A* on
a 50³ grid is ~100× slower, and scikit-image's MCP (Dijkstra, no heuristic) measured 56 ms at 50³
and 920 ms at 100³ on 2 cores against a 25 ms budget for the whole planner.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np
from numpy.typing import NDArray

_SQRT3 = float(np.sqrt(3.0))


class SearchResult(NamedTuple):
    """Outcome of :func:`astar`.

    Attributes:
        path: voxel indices from start to the reached target, shape (N, 3); empty if none.
        cost: total path cost (inf if no path).
        expanded: number of voxels expanded.
        closest: the expanded voxel nearest to a target, shape (3,) (useful when unreachable).
    """

    path: NDArray[np.int64]
    cost: float
    expanded: int
    closest: NDArray[np.int64]


@numba.njit(cache=True, nogil=True, inline="always")
def _heap_push(
    keys: np.ndarray, vals: np.ndarray, size: int, key: float, val: int
) -> None:  # pragma: no cover
    i = size
    while i > 0:
        p = (i - 1) >> 1
        if keys[p] <= key:
            break
        keys[i] = keys[p]
        vals[i] = vals[p]
        i = p
    keys[i] = key
    vals[i] = val


@numba.njit(cache=True, nogil=True, inline="always")
def _heap_pop(keys: np.ndarray, vals: np.ndarray, size: int) -> int:  # pragma: no cover
    """Remove the smallest entry of a heap of ``size`` entries; return its value."""
    top = vals[0]
    size -= 1
    key, val = keys[size], vals[size]
    i = 0
    while True:
        c = 2 * i + 1
        if c >= size:
            break
        if c + 1 < size and keys[c + 1] < keys[c]:
            c += 1
        if key <= keys[c]:
            break
        keys[i] = keys[c]
        vals[i] = vals[c]
        i = c
    keys[i] = key
    vals[i] = val
    return top


@numba.njit(cache=True, nogil=True)
def _near_kernel(blocked: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    """Voxels with a blocked voxel among their 26 neighbours (only there can a move cut a corner)."""
    nx, ny, nz = blocked.shape
    near = np.zeros_like(blocked)
    for x in range(nx):
        for y in range(ny):
            for z in range(nz):
                if blocked[x, y, z]:
                    near[max(x - 1, 0) : x + 2, max(y - 1, 0) : y + 2, max(z - 1, 0) : z + 2] = True
    return near


@numba.njit(cache=True, nogil=True)
def _astar_kernel(  # pragma: no cover - compiled
    cost: np.ndarray,
    blocked: np.ndarray,
    near_blocked: np.ndarray,
    target: np.ndarray,
    dist: np.ndarray,
    start: np.ndarray,
    length_weight: float,
    aff_scale: float,
    max_expansions: int,
) -> tuple[np.ndarray, float, int, int]:
    nx, ny, nz = cost.shape
    n = nx * ny * nz
    g = np.full(n, np.inf)
    parent = np.full(n, -1, dtype=np.int64)
    closed = np.zeros(n, dtype=np.bool_)
    cost_f = cost.ravel()
    blocked_f = blocked.ravel()
    near_f = near_blocked.ravel()
    target_f = target.ravel()
    dist_f = dist.ravel()
    s = (start[0] * ny + start[1]) * nz + start[2]
    g[s] = 0.0
    cap = n + 1
    keys = np.empty(cap, dtype=np.float64)
    vals = np.empty(cap, dtype=np.int64)
    keys[0], vals[0], size = 0.0, s, 1
    expanded = 0
    closest = s
    while size > 0:
        u = _heap_pop(keys, vals, size)
        size -= 1
        if closed[u]:
            continue
        closed[u] = True
        expanded += 1
        if dist_f[u] < dist_f[closest]:
            closest = u
        if target_f[u]:
            return parent, g[u], expanded, u
        if expanded >= max_expansions:
            break
        ux = u // (ny * nz)
        uy = (u // nz) % ny
        uz = u % nz
        check_corners = near_f[u]
        for dx in range(-1, 2):
            vx = ux + dx
            if vx < 0 or vx >= nx:
                continue
            for dy in range(-1, 2):
                vy = uy + dy
                if vy < 0 or vy >= ny:
                    continue
                for dz in range(-1, 2):
                    if dx == 0 and dy == 0 and dz == 0:
                        continue
                    vz = uz + dz
                    if vz < 0 or vz >= nz:
                        continue
                    v = (vx * ny + vy) * nz + vz
                    if closed[v] or blocked_f[v]:
                        continue
                    # no corner cutting: every voxel of the box spanned by u and v is free
                    nnz = abs(dx) + abs(dy) + abs(dz)
                    if nnz > 1 and check_corners:
                        cut = False
                        for cx in range(min(0, dx), max(0, dx) + 1):
                            for cy in range(min(0, dy), max(0, dy) + 1):
                                for cz in range(min(0, dz), max(0, dz) + 1):
                                    if cx == 0 and cy == 0 and cz == 0:
                                        continue  # u itself (a blocked start may be left)
                                    w = ((ux + cx) * ny + (uy + cy)) * nz + (uz + cz)
                                    if blocked_f[w]:
                                        cut = True
                        if cut:
                            continue
                    step = np.sqrt(nnz)
                    ng = g[u] + step * (length_weight + cost_f[v])
                    if ng < g[v]:
                        g[v] = ng
                        parent[v] = u
                        d = dist_f[v]
                        h = length_weight * d
                        if d > _SQRT3:
                            h += aff_scale * 0.5 * (d - _SQRT3) ** 2
                        if size == cap:  # grow (stale duplicates can exceed n entries)
                            cap *= 2
                            keys = np.concatenate((keys, np.empty(cap - size)))
                            vals = np.concatenate((vals, np.empty(cap - size, dtype=np.int64)))
                        _heap_push(keys, vals, size, ng + h, v)
                        size += 1
    return parent, np.inf, expanded, closest


def astar(
    cost: NDArray[np.float32],
    blocked: NDArray[np.bool_],
    target_mask: NDArray[np.bool_],
    target_distance: NDArray[np.float32],
    start: NDArray[np.int64],
    *,
    length_weight: float,
    affordance_scale: float,
    max_expansions: int | None = None,
) -> SearchResult:
    """Lowest-cost 26-connected path from ``start`` to any voxel of ``target_mask``.

    Args:
        cost: per-voxel cost >= 0, shape (X, Y, Z).
        blocked: impassable voxels, shape (X, Y, Z). The start voxel itself may be blocked (the
            search may leave it) but the path never enters another blocked voxel.
        target_mask: goal voxels, shape (X, Y, Z).
        target_distance: distance to the nearest goal voxel [voxels], shape (X, Y, Z).
        start: start voxel, shape (3,).
        length_weight: cost per voxel of path length (> 0 keeps paths short).
        affordance_scale: ``w_aff / d_max`` of the cost's affordance term, for the heuristic
            (0 gives a plain distance heuristic, always admissible).
        max_expansions: stop after expanding this many voxels (default: all of them).
    """
    blocked = np.ascontiguousarray(blocked, dtype=np.bool_)
    near_blocked = _near_kernel(blocked)
    parent, total, expanded, last = _astar_kernel(
        np.ascontiguousarray(cost, dtype=np.float32),
        blocked,
        near_blocked,
        np.ascontiguousarray(target_mask, dtype=np.bool_),
        np.ascontiguousarray(target_distance, dtype=np.float32),
        np.asarray(start, dtype=np.int64),
        float(length_weight),
        float(affordance_scale),
        int(max_expansions if max_expansions is not None else cost.size + 1),
    )
    closest = np.array(np.unravel_index(last, cost.shape), dtype=np.int64)
    if not np.isfinite(total):
        return SearchResult(np.zeros((0, 3), dtype=np.int64), float("inf"), int(expanded), closest)
    chain = [last]
    while parent[chain[-1]] >= 0:
        chain.append(int(parent[chain[-1]]))
    path = np.stack(np.unravel_index(np.array(chain[::-1]), cost.shape), axis=1).astype(np.int64)
    return SearchResult(path, float(total), int(expanded), closest)


def greedy_descent(
    cost: NDArray[np.floating],
    blocked: NDArray[np.bool_],
    start: NDArray[np.int64],
    *,
    radius: int = 2,
    max_steps: int = 300,
    visit_penalty: float = 1.0,
) -> NDArray[np.int64]:
    """The paper's released planner: repeatedly step to the cheapest voxel nearby.

    From the current voxel, look at the ``(2*radius+1)³`` neighbourhood, move to its cheapest
    free voxel, and add ``visit_penalty`` to the cost of the voxel just left. Stop when no
    neighbour is cheaper than the current voxel or after ``max_steps`` steps. Kept for
    comparison: it stalls in local minima (e.g. a U-shaped obstacle between start and target).

    Returns:
        visited voxels, shape (N, 3), starting with ``start``.
    """
    work = np.where(blocked, np.inf, cost).astype(np.float64)
    shape = np.asarray(cost.shape)
    cur = np.asarray(start, dtype=np.int64).copy()
    path = [cur.copy()]
    for _ in range(max_steps):
        lo = np.maximum(cur - radius, 0)
        hi = np.minimum(cur + radius + 1, shape)
        block = work[lo[0] : hi[0], lo[1] : hi[1], lo[2] : hi[2]]
        best = np.array(np.unravel_index(int(np.argmin(block)), block.shape)) + lo
        if not block[tuple(best - lo)] < work[tuple(cur)]:
            break
        work[tuple(cur)] += visit_penalty
        cur = best
        path.append(cur.copy())
    return np.asarray(path, dtype=np.int64)
