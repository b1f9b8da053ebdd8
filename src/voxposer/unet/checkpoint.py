"""Save and load a trained U-Net with what it needs to be used: its architecture, the cost grid
it predicts on, the instruction vocabulary and the cost scale.

A checkpoint for another cost grid or another vocabulary than the caller's is refused with a
:class:`~voxposer.errors.ConfigError` naming both (a U-Net's output layout and its embedding
table are tied to them; silently resizing would predict garbage).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

from voxposer.errors import ConfigError
from voxposer.unet._torch import torch
from voxposer.unet.model import CostUNet, UNetConfig
from voxposer.unet.vocabulary import Vocabulary

FORMAT: Final = 1


@dataclass(frozen=True)
class Checkpoint:
    """A loaded model.

    Attributes:
        model: the U-Net (in eval mode).
        config: its architecture.
        vocabulary: the instruction vocabulary it was trained with.
        grid_shape: the cost grid (X, Y, Z) [voxels] it predicts on.
        cost_scale: the model predicts cost / cost_scale.
        meta: epoch, losses and anything else saved with it.
    """

    model: CostUNet
    config: UNetConfig
    vocabulary: Vocabulary
    grid_shape: tuple[int, int, int]
    cost_scale: float
    meta: dict[str, Any]


def save_checkpoint(path: Path, model: CostUNet, vocabulary: Vocabulary,
                    grid_shape: tuple[int, ...], cost_scale: float,
                    meta: dict[str, Any] | None = None) -> Path:
    """Write ``model`` and its context to ``path`` (atomically); returns ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    payload = {"format": FORMAT, "config": model.config.to_json(),
               "vocabulary": list(vocabulary.words), "grid_shape": [int(n) for n in grid_shape],
               "cost_scale": float(cost_scale), "meta": dict(meta or {}),
               "state_dict": model.state_dict()}
    tmp = path.with_suffix(path.suffix + ".tmp")
    torch.save(payload, tmp)
    tmp.replace(path)
    return path


def load_checkpoint(path: Path, *, grid_shape: tuple[int, ...] | None = None,
                    vocabulary: Vocabulary | None = None) -> Checkpoint:
    """The checkpoint at ``path``; with ``grid_shape`` / ``vocabulary`` given, refuse one made
    for another cost grid / vocabulary (ConfigError naming both)."""
    path = Path(path)
    if not path.exists():
        raise ConfigError(f"no U-Net checkpoint at {path}")
    payload = torch.load(path, map_location="cpu", weights_only=True)
    if payload.get("format") != FORMAT:
        raise ConfigError(f"{path} has checkpoint format {payload.get('format')!r}; this version "
                          f"reads format {FORMAT}")
    saved_shape = tuple(int(n) for n in payload["grid_shape"])
    if grid_shape is not None and tuple(grid_shape) != saved_shape:
        raise ConfigError(f"{path} predicts on a cost grid of shape {saved_shape}, but this "
                          f"planner's cost grid has shape {tuple(grid_shape)}")
    saved_vocab = Vocabulary(tuple(payload["vocabulary"]))
    if vocabulary is not None and vocabulary.words != saved_vocab.words:
        raise ConfigError(f"{path} was trained with a vocabulary of shape ({len(saved_vocab)},) "
                          f"but the given vocabulary has shape ({len(vocabulary)},)"
                          + ("" if len(saved_vocab) != len(vocabulary) else
                             " (same size, different words)"))
    config = UNetConfig(**payload["config"])
    model = CostUNet(config, len(saved_vocab), saved_shape[2])
    model.load_state_dict(payload["state_dict"])
    model.eval()
    return Checkpoint(model, config, saved_vocab, (saved_shape[0], saved_shape[1], saved_shape[2]),
                      float(payload["cost_scale"]), dict(payload["meta"]))


__all__ = ["Checkpoint", "load_checkpoint", "save_checkpoint"]
