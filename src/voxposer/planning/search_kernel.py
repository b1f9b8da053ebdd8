"""The compiled core of the global path search: a binary heap and A* over a flat voxel grid.

Kept apart from :mod:`voxposer.planning.search` (the typed Python entry point) because it is
numba code: flat indices, no Python objects. Moves, costs and the heuristic are described there.
Compiled once per machine and cached on disk.

Where the time goes (2 shared cores, ``benchmarks/planner.py``'s scenes at 50³): ~10k expansions
of ~1 µs each, about a third of it in the heap (29k pushes and pops, ~100 ns per operation
here). Two rewrites measured no faster on these scenes: a precomputed neighbour table with
bounds checked only on the grid's faces (10.7–11.7 ms against 9.5–12.1 ms), and one int64 heap
of packed (float32 key, index) entries (3.0 ms against 3.7 ms for the heap alone).
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

SQRT3 = float(np.sqrt(3.0))


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
def astar_kernel(  # pragma: no cover - compiled
    cost: np.ndarray,
    blocked: np.ndarray,
    near_blocked: np.ndarray,
    target: np.ndarray,
    dist: np.ndarray,
    start: np.ndarray,
    length_weight: float,
    aff_scale: float,
    max_expansions: int,
) -> tuple[np.ndarray, float, int, int, bool]:
    """A* from ``start``; returns (parent index per voxel, cost of the reached target or inf,
    voxels expanded, the target reached or the expanded voxel nearest one, whether the search
    stopped at ``max_expansions`` rather than reaching a target or running out of voxels)."""
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
            return parent, g[u], expanded, u, False
        if expanded >= max_expansions:
            return parent, np.inf, expanded, closest, True
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
                        if d > SQRT3:
                            h += aff_scale * 0.5 * d * (d - SQRT3)
                        if size == cap:  # grow (stale duplicates can exceed n entries)
                            cap *= 2
                            keys = np.concatenate((keys, np.empty(cap - size)))
                            vals = np.concatenate((vals, np.empty(cap - size, dtype=np.int64)))
                        _heap_push(keys, vals, size, ng + h, v)
                        size += 1
    return parent, np.inf, expanded, closest, False


def near_blocked(blocked: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Voxels with a blocked voxel among their 26 neighbours or themselves (only from there can
    a diagonal move cut a corner), shape ``blocked.shape``: a 3×3×3 dilation, one axis at a
    time."""
    near = blocked.copy()
    for axis in range(3):
        grown = near.copy()
        lo = [slice(None)] * 3
        hi = [slice(None)] * 3
        lo[axis], hi[axis] = slice(None, -1), slice(1, None)
        grown[tuple(hi)] |= near[tuple(lo)]
        grown[tuple(lo)] |= near[tuple(hi)]
        near = grown
    return near


@numba.njit(cache=True, nogil=True)
def sealed_off(  # pragma: no cover - compiled
    blocked: np.ndarray, target: np.ndarray, start: np.ndarray, budget: int
) -> bool:
    """Whether the targets' free face-connected space is smaller than ``budget`` voxels and
    does not hold ``start`` (a flood fill from every target voxel, stopped after ``budget``
    voxels): then no path can reach a target, which this proves in a few hundred µs where a
    search from the start would first expand everything it can reach."""
    nx, ny, nz = blocked.shape
    n = nx * ny * nz
    blocked_f, target_f = blocked.ravel(), target.ravel()
    s = (start[0] * ny + start[1]) * nz + start[2]
    seen = np.zeros(n, dtype=np.bool_)
    queue = np.empty(budget, dtype=np.int64)
    head, tail = 0, 0
    for u in range(n):
        if target_f[u]:
            if tail == budget:
                return False
            seen[u] = True
            queue[tail] = u
            tail += 1
    while head < tail:
        u = queue[head]
        head += 1
        if u == s:
            return False
        ux, uy, uz = u // (ny * nz), (u // nz) % ny, u % nz
        for axis in range(3):
            for sign in (-1, 1):
                vx, vy, vz = ux, uy, uz
                if axis == 0:
                    vx += sign
                elif axis == 1:
                    vy += sign
                else:
                    vz += sign
                if vx < 0 or vx >= nx or vy < 0 or vy >= ny or vz < 0 or vz >= nz:
                    continue
                v = (vx * ny + vy) * nz + vz
                if seen[v] or (blocked_f[v] and v != s):
                    continue
                if tail == budget:
                    return False
                seen[v] = True
                queue[tail] = v
                tail += 1
    return True
