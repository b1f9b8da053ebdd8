"""Voxel-volume operations behind cost-map composition: pooling, distances, smoothing, spheres.

Each is exact and vectorised; shapes are (X, Y, Z) voxel volumes.
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from voxposer.geometry.voxel_grid import VoxelGrid


def pool_max(volume: NDArray, factor: int) -> NDArray:
    """Block maximum over ``factor``³ cells, padding the upper side with the array minimum.

    ``volume`` has shape (X, Y, Z); the result has shape ``ceil((X, Y, Z) / factor)``. Reduced
    one axis at a time (each pass on the already smaller volume: ~2× faster at 100³ than taking
    the maximum of the ``factor``³ strided views), each pass's first maximum written straight
    into its result (no copy of the first view: 0.47 against 0.56 ms for a float32 100³ volume,
    0.24 against 0.31 ms for a boolean one, one quiet process).
    """
    if factor == 1:
        return volume
    shape = np.asarray(volume.shape)
    padded_shape = -(-shape // factor) * factor
    if np.any(padded_shape != shape):
        fill = False if volume.dtype == bool else volume.min()
        padded = np.full(padded_shape, fill, dtype=volume.dtype)
        padded[: shape[0], : shape[1], : shape[2]] = volume
        volume = padded
    for axis in range(3):
        lead = (slice(None),) * axis
        views = [volume[(*lead, slice(i, None, factor))] for i in range(factor)]
        out = np.maximum(views[0], views[1])
        for view in views[2:]:
            np.maximum(out, view, out=out)
        volume = out
    return volume


def nonzero_voxels(mask: NDArray) -> NDArray[np.intp]:
    """Indices of the nonzero voxels of ``mask`` (shape (X, Y, Z)), shape (N, 3), in C order:
    ``np.argwhere(mask)``, the same array, taken through the flat indices (on a 100³ grid about
    10× faster than ``argwhere``'s n-dimensional scan)."""
    return np.stack(np.unravel_index(np.flatnonzero(mask), mask.shape), axis=1)


def normalise(values: NDArray[np.float32]) -> NDArray[np.float32]:
    lo, hi = float(values.min()), float(values.max())
    if hi - lo < 1e-12:
        return np.zeros_like(values)
    values -= lo
    values *= 1.0 / (hi - lo)
    return values


def distance_to(mask: NDArray[np.bool_], voxels: NDArray[np.int64]) -> NDArray[np.float32]:
    """Euclidean distance [voxels] from every voxel to the nearest True voxel of ``mask``.

    ``voxels`` lists the True voxels, shape (K, 3). A handful of targets (the usual case: a point
    above an object) is done by broadcasting; larger regions by scipy's distance transform.
    """
    if len(voxels) > 8:
        return ndimage.distance_transform_edt(~mask).astype(np.float32)
    axes = [np.arange(n, dtype=np.float32) for n in mask.shape]
    best = np.full(mask.shape, np.inf, dtype=np.float32)
    for v in voxels:
        dx, dy, dz = ((axes[a] - v[a]) ** 2 for a in range(3))
        np.minimum(best, dx[:, None, None] + dy[None, :, None] + dz[None, None, :], out=best)
    return np.sqrt(best, out=best)


def smooth_zero_padded(
    volume: NDArray[np.float32], sigma: float, truncate: float
) -> NDArray[np.float32]:
    """Gaussian filter (zero outside the grid), run only where the result can be non-zero.

    The kernel is cut at ``truncate * sigma`` voxels, so outside the bounding box of the non-zero
    input grown by that radius the output is exactly zero; the result equals
    ``scipy.ndimage.gaussian_filter(volume, sigma, truncate=truncate, mode="constant")`` (the
    same normalised weights) to float32 rounding. Each axis's pass is one matrix product with
    the banded matrix of those weights: on the planner benchmark's scenes (50³ planning grid)
    0.5 ms against 1.7–1.9 ms for scipy's one-dimensional correlations (2 cores, median).
    """
    radius = int(truncate * sigma + 0.5)
    lo, hi = [], []
    for axis in range(3):
        other = tuple(a for a in range(3) if a != axis)
        nz = np.flatnonzero(volume.any(axis=other))
        if not len(nz):
            return np.zeros_like(volume)
        lo.append(max(int(nz[0]) - radius, 0))
        hi.append(min(int(nz[-1]) + radius + 1, volume.shape[axis]))
    box = (slice(lo[0], hi[0]), slice(lo[1], hi[1]), slice(lo[2], hi[2]))
    part = np.asarray(volume[box], dtype=np.float32)
    m0, m1, m2 = part.shape
    # one small product per slice (numpy's batched matmul): BLAS keeps products this small on
    # one thread, where one large product spreads over threads that wait on busy cores
    part = np.matmul(_gaussian_band(m0, sigma, radius), part.transpose(2, 0, 1))  # (m2, m0, m1)
    part = np.matmul(part, _gaussian_band(m1, sigma, radius).T).transpose(1, 2, 0)  # (m0, m1, m2)
    part = np.matmul(part, _gaussian_band(m2, sigma, radius).T)
    out = np.zeros_like(volume)
    out[box] = part
    return out


@functools.lru_cache(maxsize=64)
def _gaussian_band(size: int, sigma: float, radius: int) -> NDArray[np.float32]:
    """The (size, size) matrix of one Gaussian pass with zero padding: entry (i, j) is the
    weight of input j in output i, ``exp(-(j - i)² / 2σ²)`` normalised over ``|j - i| <= radius``
    (as scipy.ndimage's kernel), 0 beyond. Read-only (cached)."""
    x = np.arange(-radius, radius + 1, dtype=np.float64)
    weights = np.exp(-0.5 / (sigma * sigma) * x**2)
    weights /= weights.sum()
    offset = np.arange(size)[None, :] - np.arange(size)[:, None]
    band = np.where(np.abs(offset) <= radius,
                    weights[np.clip(offset + radius, 0, 2 * radius)], 0.0).astype(np.float32)
    band.flags.writeable = False
    return band


def ball(radius_voxels: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Ellipsoidal structuring element with the given per-axis radii [voxels]."""
    r = np.floor(radius_voxels).astype(int)
    axes = [np.arange(-r[a], r[a] + 1) / max(radius_voxels[a], 1e-9) for a in range(3)]
    x, y, z = np.meshgrid(*axes, indexing="ij", sparse=True)
    return np.asarray(x**2 + y**2 + z**2 <= 1.0 + 1e-9)


def clear_sphere(
    mask: NDArray[np.bool_], grid: VoxelGrid, centre: NDArray, radius_cm: float
) -> None:
    """Set ``mask`` False within ``radius_cm`` of world point ``centre`` [m] (in place)."""
    if radius_cm <= 0:
        return
    c = grid.world_to_voxel(centre, clip=True)
    reach = np.ceil(radius_cm / 100.0 / grid.resolution).astype(int)
    lo = np.maximum(c - reach, 0)
    hi = np.minimum(c + reach + 1, np.asarray(grid.shape))
    axes = [
        grid.voxel_to_world(np.zeros(3))[a] + np.arange(lo[a], hi[a]) * grid.resolution[a]
        for a in range(3)
    ]
    x, y, z = np.meshgrid(*axes, indexing="ij", sparse=True)
    inside = (x - centre[0]) ** 2 + (y - centre[1]) ** 2 + (z - centre[2]) ** 2 <= (
        radius_cm / 100.0
    ) ** 2
    mask[lo[0] : hi[0], lo[1] : hi[1], lo[2] : hi[2]] &= ~inside
