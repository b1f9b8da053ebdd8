"""A trained U-Net's cost map, in the type the planner's search runs on
(:class:`voxposer.valuemaps.cost.CostMap`).

The U-Net predicts the cost volume; the target is where the predicted cost is lowest (every
planning voxel within ``target_tolerance`` of the minimum, in normalised cost). Everything the
search needs besides the cost — the target mask and distance, the scene's obstacles cleared
around the start and the target — is composed by :func:`voxposer.valuemaps.cost.compose_cost_map`
from that target exactly as for VoxPoser's own maps, and ``cost`` is the U-Net's.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.unet._torch import torch
from voxposer.unet.checkpoint import Checkpoint, load_checkpoint
from voxposer.unet.encoding import ObservationVoxels, encode, target_to_cost, voxelise
from voxposer.valuemaps.cost import CostMap, CostMapConfig, compose_cost_map


def _voxels(observation: Any, coarse: VoxelGrid) -> ObservationVoxels:
    """``observation`` as voxels on ``coarse``: ObservationVoxels as they are, a point cloud
    (``.points`` [m] (N, 3), ``.colors`` (N, 3) uint8) voxelised."""
    if isinstance(observation, ObservationVoxels):
        return observation
    return voxelise(observation.points, observation.colors, coarse)


def predict_cost(checkpoint: Checkpoint, observation: ObservationVoxels,
                 instruction: str) -> NDArray[np.float32]:
    """The predicted cost, shape ``checkpoint.grid_shape``, in the planner's units
    ([0, cost_scale] for a well-trained model)."""
    if observation.occupancy.shape != checkpoint.grid_shape:
        raise ConfigError(f"the observation has shape {observation.occupancy.shape} but the "
                          f"checkpoint predicts on a cost grid of shape {checkpoint.grid_shape}")
    enc = checkpoint.config.encoding
    obs = torch.from_numpy(encode(observation.occupancy[None], observation.colour[None], enc))
    tokens = torch.from_numpy(checkpoint.vocabulary.batch([instruction]))
    checkpoint.model.eval()
    with torch.no_grad():
        out = checkpoint.model(obs, tokens).numpy()
    return target_to_cost(out, enc)[0] * np.float32(checkpoint.cost_scale)


def predict_cost_map(checkpoint: Checkpoint | Path, observation: Any, instruction: str, *,
                     grid: VoxelGrid, start: ArrayLike,
                     occupancy: NDArray[np.bool_] | None = None,
                     config: CostMapConfig | None = None,
                     target_tolerance: float = 0.01,
                     entity_occupancy: NDArray[np.bool_] | None = None,
                     layer_z: float | None = None,
                     off_limits: NDArray[np.bool_] | None = None) -> CostMap:
    """The planner's cost map for ``instruction`` in the observed scene, from the U-Net.

    Args:
        checkpoint: a loaded checkpoint or its path.
        observation: :class:`ObservationVoxels` on the planning grid, or a point cloud.
        instruction: the instruction (unknown words read as the unknown token).
        grid: the workspace (fine) grid; ``grid.coarsen(config.downsample)`` must have the
            checkpoint's grid shape (else ConfigError naming both shapes).
        start: the entity's position [m], shape (3,).
        occupancy: scene obstacle voxels on ``grid``, shape ``grid.shape`` (None: free space).
        config: cost-map parameters (the end-effector planner's when the data was made with
            it; defaults when None).
        target_tolerance: target voxels lie within this of the minimum (normalised cost).
        entity_occupancy: the moving entity's own voxels on ``grid`` (not obstacles).
        layer_z: an object sliding on the table at this height [m]: the target is the lowest
            cost within its planning layer, and the path stays in that layer (None: anywhere).
        off_limits: voxels the path may not enter, shape ``grid.shape`` (as
            :func:`~voxposer.valuemaps.cost.compose_cost_map`; the target is chosen anywhere).
    """
    cfg = config or CostMapConfig()
    coarse = grid.coarsen(cfg.downsample)
    ckpt = checkpoint if isinstance(checkpoint, Checkpoint) else load_checkpoint(
        Path(checkpoint), grid_shape=coarse.shape)
    if ckpt.grid_shape != coarse.shape:
        raise ConfigError(f"the checkpoint predicts on a cost grid of shape {ckpt.grid_shape}, "
                          f"but this planner's cost grid has shape {coarse.shape}")
    cost = predict_cost(ckpt, _voxels(observation, coarse), instruction)
    allowed = np.ones(cost.shape, dtype=bool)
    if layer_z is not None:
        start_m = np.asarray(start, dtype=np.float64).reshape(3)
        kz = int(coarse.world_to_voxel([start_m[0], start_m[1], layer_z], clip=True)[2])
        allowed[:] = False
        allowed[:, :, kz] = True
    lowest = float(cost[allowed].min())
    target = allowed & (cost <= lowest + target_tolerance * ckpt.cost_scale)
    f = cfg.downsample
    fine = np.repeat(np.repeat(np.repeat(target, f, 0), f, 1), f, 2)[
        :grid.shape[0], :grid.shape[1], :grid.shape[2]]
    base = compose_cost_map(grid, fine.astype(np.float32), start, occupancy=occupancy,
                            entity_occupancy=entity_occupancy,
                            config=replace(cfg, avoidance_keep_out=0.0), layer_z=layer_z,
                            off_limits=off_limits)
    residual = np.clip(cost - cfg.affordance_weight * base.affordance_cost, 0, None)
    avoidance = (residual / cfg.avoidance_weight if cfg.avoidance_weight > 0
                 else np.zeros_like(residual))
    return replace(base, cost=cost.astype(np.float32),
                   avoidance_cost=np.clip(avoidance, 0, 1).astype(np.float32))


__all__ = ["predict_cost", "predict_cost_map"]
