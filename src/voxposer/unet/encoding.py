"""The observation at the planner's cost grid, and the two model input layouts (NumPy only).

The planner's cost map lives on the workspace grid coarsened by ``CostMapConfig.downsample``
(50³ voxels for the default 100³ workspace). The observation — the fused RGB point cloud of the
four cameras — is voxelised onto that same grid as :class:`ObservationVoxels` (occupancy and mean
colour per voxel); this is what the training data stores. A model reads one of two encodings:

* ``"voxel"`` — channels (occupancy, R, G, B) over the 3-D grid, shape (4, X, Y, Z), for a
  3-D U-Net that predicts the cost volume, shape (1, X, Y, Z).
* ``"topdown"`` — 2.5D: per (x, y) column the height of its highest occupied voxel and that
  voxel's colour, shape (4, X, Y), for a 2-D U-Net that predicts the cost volume's Z slices as
  channels, shape (Z, X, Y).

``benchmarks/results/unet_library.txt`` has the measurement that chose ``"topdown"``.
"""

from __future__ import annotations

from typing import Final, Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid

Encoding = Literal["voxel", "topdown"]
ENCODINGS: Final[tuple[Encoding, ...]] = ("voxel", "topdown")
#: the encoding the measurement chose (see the module docs).
DEFAULT_ENCODING: Final[Encoding] = "topdown"
#: input channels of either encoding.
IN_CHANNELS: Final = 4


def check_encoding(name: str) -> Encoding:
    """``name`` if it is one of :data:`ENCODINGS`; else ConfigError listing them."""
    for known in ENCODINGS:
        if name == known:
            return known
    raise ConfigError(f"unknown encoding {name!r}; encodings are: {', '.join(ENCODINGS)}")


class ObservationVoxels(NamedTuple):
    """A point cloud voxelised on the cost grid.

    Attributes:
        occupancy: 1 where at least one point fell, shape (X, Y, Z), uint8.
        colour: mean RGB of the voxel's points (0 where empty), shape (X, Y, Z, 3), uint8.
    """

    occupancy: NDArray[np.uint8]
    colour: NDArray[np.uint8]


def voxelise(points: ArrayLike, colours: ArrayLike, grid: VoxelGrid) -> ObservationVoxels:
    """Voxelise world points [m], shape (N, 3), with RGB ``colours``, shape (N, 3) in 0..255,
    onto ``grid`` (the cost grid); points outside the workspace are dropped."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    c = np.asarray(colours, dtype=np.float64).reshape(-1, 3)
    if len(p) != len(c):
        raise ConfigError(f"{len(p)} points but {len(c)} colours")
    shape = np.asarray(grid.shape)
    scaled = (p - grid.bounds_min) / grid.resolution
    inside = np.all((scaled >= 0) & (scaled <= shape), axis=1)
    idx = np.minimum(scaled[inside].astype(np.int64), shape - 1)
    flat = np.ravel_multi_index(idx.T, grid.shape)
    size = int(np.prod(shape))
    count = np.bincount(flat, minlength=size).astype(np.float64)
    sums = np.stack([np.bincount(flat, weights=c[inside, k], minlength=size) for k in range(3)],
                    axis=1)
    mean = sums / np.maximum(count, 1.0)[:, None]
    occupancy = (count > 0).astype(np.uint8).reshape(grid.shape)
    colour = np.clip(np.rint(mean), 0, 255).astype(np.uint8).reshape(*grid.shape, 3)
    return ObservationVoxels(occupancy, colour)


def encode(occupancy: NDArray[np.uint8], colour: NDArray[np.uint8],
           encoding: Encoding) -> NDArray[np.float32]:
    """Model input of a batch of observations.

    Args:
        occupancy: shape (B, X, Y, Z), 0/1.
        colour: shape (B, X, Y, Z, 3), 0..255.
        encoding: ``"voxel"`` → (B, 4, X, Y, Z); ``"topdown"`` → (B, 4, X, Y) with channel 0 the
            column's top height (k + 1) / Z (0: empty column) and channels 1..3 its RGB / 255.
    """
    occ = np.asarray(np.asarray(occupancy) > 0, dtype=bool)
    rgb = np.asarray(colour, dtype=np.float32) / 255.0
    if check_encoding(encoding) == "voxel":
        return np.concatenate([occ[:, None].astype(np.float32),
                               np.moveaxis(rgb, -1, 1)], axis=1)
    depth = occ.shape[-1]
    # index of the highest occupied voxel per column (argmax of the reversed column)
    top = depth - 1 - np.argmax(occ[..., ::-1], axis=-1)
    filled = np.asarray(occ.any(axis=-1), dtype=bool)
    height = np.where(filled, (top + 1) / depth, 0.0).astype(np.float32)
    top_rgb = np.take_along_axis(rgb, top[..., None, None], axis=-2)[..., 0, :]
    top_rgb = np.where(filled[..., None], top_rgb, 0.0).astype(np.float32)
    return np.concatenate([height[:, None], np.moveaxis(top_rgb, -1, 1)], axis=1)


def cost_to_target(cost: NDArray[np.floating], encoding: Encoding) -> NDArray[np.float32]:
    """A batch of cost volumes, shape (B, X, Y, Z), in the model's output layout:
    (B, 1, X, Y, Z) for ``"voxel"``, (B, Z, X, Y) for ``"topdown"``."""
    c = np.asarray(cost, dtype=np.float32)
    if check_encoding(encoding) == "voxel":
        return c[:, None]
    return np.ascontiguousarray(np.moveaxis(c, -1, 1))


def target_to_cost(target: NDArray[np.floating], encoding: Encoding) -> NDArray[np.float32]:
    """The inverse of :func:`cost_to_target`: (B, X, Y, Z)."""
    t = np.asarray(target, dtype=np.float32)
    if check_encoding(encoding) == "voxel":
        return t[:, 0]
    return np.ascontiguousarray(np.moveaxis(t, 1, -1))


__all__ = ["DEFAULT_ENCODING", "ENCODINGS", "IN_CHANNELS", "Encoding", "ObservationVoxels",
           "check_encoding", "cost_to_target", "encode", "target_to_cost", "voxelise"]
