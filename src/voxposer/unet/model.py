"""A language-conditioned U-Net predicting the planner's normalised cost map.

Encoder–decoder with skip connections (Ronneberger et al. [122]; 3-D after Çiçek et al. [123])
whose every block is FiLM-modulated by the instruction embedding: ``x · (1 + γ) + β`` with
(γ, β) a linear function of the embedding. ``encoding="topdown"`` builds a 2-D U-Net over (x, y)
predicting the Z slices as channels; ``"voxel"`` a 3-D U-Net predicting one channel (see
:mod:`voxposer.unet.encoding`). Sizes need not be powers of two: pooling rounds up and each
decoder level is resized to its skip connection.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from voxposer.errors import ConfigError
from voxposer.unet._torch import nn, torch
from voxposer.unet.encoding import IN_CHANNELS, Encoding, check_encoding
from voxposer.unet.instruction import InstructionEncoder


@dataclass(frozen=True)
class UNetConfig:
    """Architecture of :class:`CostUNet`.

    Attributes:
        encoding: the observation encoding, "topdown" (2-D U-Net) or "voxel" (3-D U-Net).
        base_channels: channels of the first level; level k has ``base_channels · 2^k``.
        depth: number of pooling steps (levels − 1).
        embed_dim: width of the instruction embedding.
    """

    encoding: Encoding = "topdown"
    base_channels: int = 32
    depth: int = 3
    embed_dim: int = 32

    def __post_init__(self) -> None:
        check_encoding(self.encoding)
        for name, lo in (("base_channels", 1), ("depth", 1), ("embed_dim", 1)):
            value = getattr(self, name)
            if not isinstance(value, int) or value < lo:
                raise ConfigError(f"UNetConfig.{name} must be an int >= {lo}; got {value!r}")

    def to_json(self) -> dict[str, Any]:
        """A JSON-serialisable dict (checkpoints)."""
        return {"encoding": self.encoding, "base_channels": self.base_channels,
                "depth": self.depth, "embed_dim": self.embed_dim}


class _Block(nn.Module):
    """Two (conv, group norm, ReLU) layers, FiLM-modulated by the instruction embedding."""

    def __init__(self, dims: int, c_in: int, c_out: int, embed_dim: int) -> None:
        super().__init__()
        conv = nn.Conv2d if dims == 2 else nn.Conv3d
        groups = 4 if c_out % 4 == 0 else 1
        self.body = nn.Sequential(
            conv(c_in, c_out, 3, padding=1), nn.GroupNorm(groups, c_out), nn.ReLU(inplace=True),
            conv(c_out, c_out, 3, padding=1), nn.GroupNorm(groups, c_out), nn.ReLU(inplace=True))
        self.film = nn.Linear(embed_dim, 2 * c_out)
        self.dims = dims

    def forward(self, x: torch.Tensor, emb: torch.Tensor) -> torch.Tensor:
        gamma, beta = self.film(emb).chunk(2, dim=1)
        shape = (*gamma.shape, *([1] * self.dims))
        return self.body(x) * (1 + gamma.view(shape)) + beta.view(shape)


class CostUNet(nn.Module):
    """Observation (B, 4, X, Y[, Z]) and token ids (B, L) → normalised cost in the encoding's
    output layout: (B, Z, X, Y) for "topdown", (B, 1, X, Y, Z) for "voxel".

    Args:
        config: the architecture.
        vocab_size: tokens of the instruction vocabulary.
        depth_voxels: Z of the cost grid (the output channels of the "topdown" U-Net).
    """

    def __init__(self, config: UNetConfig, vocab_size: int, depth_voxels: int) -> None:
        super().__init__()
        self.config = config
        dims = 2 if config.encoding == "topdown" else 3
        out_channels = depth_voxels if dims == 2 else 1
        widths = [config.base_channels * 2 ** k for k in range(config.depth + 1)]
        self.instruction = InstructionEncoder(vocab_size, config.embed_dim)
        e = config.embed_dim
        self.down = nn.ModuleList(
            [_Block(dims, IN_CHANNELS if k == 0 else widths[k - 1], widths[k], e)
             for k in range(len(widths))])
        self.up = nn.ModuleList(
            [_Block(dims, widths[k + 1] + widths[k], widths[k], e)
             for k in reversed(range(config.depth))])
        conv = nn.Conv2d if dims == 2 else nn.Conv3d
        self.head = conv(widths[0], out_channels, 1)
        self.pool = (nn.MaxPool2d if dims == 2 else nn.MaxPool3d)(2, ceil_mode=True)

    def forward(self, obs: torch.Tensor, token_ids: torch.Tensor) -> torch.Tensor:
        emb = self.instruction(token_ids)
        skips = []
        x = obs
        for k, block in enumerate(self.down):
            x = block(x if k == 0 else self.pool(x), emb)
            skips.append(x)
        for block, skip in zip(self.up, reversed(skips[:-1]), strict=True):
            x = nn.functional.interpolate(x, size=skip.shape[2:], mode="nearest")
            x = block(torch.cat([x, skip], dim=1), emb)
        out: torch.Tensor = self.head(x)
        return out

    def parameter_count(self) -> int:
        """Trainable parameters."""
        return sum(p.numel() for p in self.parameters() if p.requires_grad)


__all__ = ["CostUNet", "UNetConfig"]
