"""Training the cost U-Net: Adam on the MSE (or smooth-L1) of the normalised cost map.

:func:`train` reads a ``voxposer bench-data`` folder, trains for ``epochs`` passes in shuffled
minibatches, writes ``checkpoints/epoch_NNN.pt`` and ``model.pt`` (the latest) after every epoch,
and ``loss.png`` / ``losses.json`` (the per-step and per-epoch loss). All randomness (weight
init, shuffling) comes from one numpy Generator seeded with ``TrainConfig.seed``.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.plotting import pyplot, save_figure
from voxposer.unet._torch import nn, torch
from voxposer.unet.checkpoint import save_checkpoint
from voxposer.unet.dataset import Dataset, load_dataset
from voxposer.unet.encoding import cost_to_target, encode
from voxposer.unet.model import CostUNet, UNetConfig
from voxposer.unet.vocabulary import Vocabulary

Loss = Literal["mse", "smooth_l1"]


@dataclass(frozen=True)
class TrainConfig:
    """Training parameters.

    Attributes:
        epochs: passes over the data.
        batch_size: samples per Adam step.
        learning_rate: Adam's step size.
        loss: "mse" or "smooth_l1" (Huber, beta 0.1) on cost / cost_scale.
        seed: seeds the numpy Generator all randomness is drawn from.
        threads: torch CPU threads (1 on a busy machine; see nn_library.txt).
        model: the architecture.
    """

    epochs: int = 20
    batch_size: int = 8
    learning_rate: float = 1e-3
    loss: Loss = "mse"
    seed: int = 0
    threads: int = 1
    model: UNetConfig = field(default_factory=UNetConfig)

    def __post_init__(self) -> None:
        for name in ("epochs", "batch_size", "threads"):
            value = getattr(self, name)
            if not isinstance(value, int) or value < 1:
                raise ConfigError(f"TrainConfig.{name} must be an int >= 1; got {value!r}")
        if not (np.isfinite(self.learning_rate) and self.learning_rate > 0):
            raise ConfigError(f"TrainConfig.learning_rate must be > 0; got {self.learning_rate!r}")
        if self.loss not in ("mse", "smooth_l1"):
            raise ConfigError(f"TrainConfig.loss must be 'mse' or 'smooth_l1'; got {self.loss!r}")


class Batch(NamedTuple):
    """Model inputs and target: obs (B, 4, X, Y[, Z]), tokens (B, L), target in the encoding's
    output layout (see :func:`voxposer.unet.encoding.cost_to_target`), normalised cost."""

    obs: torch.Tensor
    tokens: torch.Tensor
    target: torch.Tensor


class TrainResult(NamedTuple):
    """Per-step losses, per-epoch mean losses, and the last checkpoint written."""

    step_losses: list[float]
    epoch_losses: list[float]
    checkpoint: Path


#: called after each step with (epoch, step in epoch, steps per epoch, loss).
StepCallback = Callable[[int, int, int, float], None]


def make_batch(data: Dataset, index: NDArray[np.int64], vocabulary: Vocabulary,
               config: UNetConfig) -> Batch:
    """The samples ``index`` of ``data``, encoded (cost divided by the dataset's cost scale)."""
    return batch_from_arrays(data.occupancy[index], data.colour[index], data.cost[index],
                             [data.instruction[i] for i in index], vocabulary, config,
                             float(data.manifest["cost_scale"]))


def batch_from_arrays(occupancy: NDArray[np.uint8], colour: NDArray[np.uint8],
                      cost: NDArray[np.float32], instructions: list[str],
                      vocabulary: Vocabulary, config: UNetConfig, cost_scale: float) -> Batch:
    """A batch from observation voxels (B, X, Y, Z) and (B, X, Y, Z, 3), cost maps
    (B, X, Y, Z) and B instructions; the target is ``cost / cost_scale``."""
    obs = encode(occupancy, colour, config.encoding)
    target = cost_to_target(np.asarray(cost, dtype=np.float32) / cost_scale, config.encoding)
    return Batch(torch.from_numpy(obs), torch.from_numpy(vocabulary.batch(instructions)),
                 torch.from_numpy(target))


def make_model(config: UNetConfig, vocabulary: Vocabulary, grid_shape: tuple[int, ...],
               rng: np.random.Generator) -> CostUNet:
    """A freshly initialised U-Net, its weights drawn from a seed taken from ``rng``."""
    torch.manual_seed(int(rng.integers(2**62)))
    return CostUNet(config, len(vocabulary), int(grid_shape[2]))


def loss_fn(pred: torch.Tensor, target: torch.Tensor, loss: Loss) -> torch.Tensor:
    """Mean MSE or smooth-L1 (beta 0.1) over every voxel of the batch."""
    if loss == "mse":
        return nn.functional.mse_loss(pred, target)
    return nn.functional.smooth_l1_loss(pred, target, beta=0.1)


def train_step(model: CostUNet, optimiser: torch.optim.Optimizer, batch: Batch,
               loss: Loss = "mse") -> float:
    """One Adam step on ``batch``; returns its loss (before the step)."""
    model.train()
    optimiser.zero_grad()
    value = loss_fn(model(batch.obs, batch.tokens), batch.target, loss)
    value.backward()
    optimiser.step()
    return float(value.detach())


def train(data_dir: Path, out_dir: Path, config: TrainConfig | None = None,
          on_step: StepCallback | None = None) -> TrainResult:
    """Train on ``data_dir`` (a ``voxposer bench-data`` folder) into ``out_dir``."""
    cfg = config or TrainConfig()
    torch.set_num_threads(cfg.threads)
    data = load_dataset(Path(data_dir))
    vocabulary = Vocabulary(tuple(data.manifest["vocabulary"]))
    grid_shape = tuple(int(n) for n in data.manifest["grid_shape"])
    rng = np.random.default_rng(cfg.seed)
    model = make_model(cfg.model, vocabulary, grid_shape, rng)
    optimiser = torch.optim.Adam(model.parameters(), lr=cfg.learning_rate)
    out = Path(out_dir)
    n = len(data.instruction)
    steps = -(-n // cfg.batch_size)
    step_losses: list[float] = []
    epoch_losses: list[float] = []
    last = out / "model.pt"
    for epoch in range(1, cfg.epochs + 1):
        order = rng.permutation(n)
        losses = []
        for k in range(steps):
            batch = make_batch(data, order[k * cfg.batch_size:(k + 1) * cfg.batch_size],
                               vocabulary, cfg.model)
            losses.append(train_step(model, optimiser, batch, cfg.loss))
            if on_step is not None:
                on_step(epoch, k + 1, steps, losses[-1])
        step_losses += losses
        epoch_losses.append(float(np.mean(losses)))
        meta = {"epoch": epoch, "epoch_losses": epoch_losses, "loss": cfg.loss,
                "samples": n, "data": str(data_dir)}
        scale = float(data.manifest["cost_scale"])
        save_checkpoint(out / "checkpoints" / f"epoch_{epoch:03d}.pt", model, vocabulary,
                        grid_shape, scale, meta)
        save_checkpoint(last, model, vocabulary, grid_shape, scale, meta)
        write_losses(out, step_losses, epoch_losses, steps)
    return TrainResult(step_losses, epoch_losses, last)


def write_losses(out: Path, step_losses: list[float], epoch_losses: list[float],
                 steps_per_epoch: int) -> Path:
    """``losses.json`` and the loss curve ``loss.png`` (log scale) in ``out``; returns the PNG."""
    plt = pyplot("the U-Net loss curve")
    out.mkdir(parents=True, exist_ok=True)
    (out / "losses.json").write_text(json.dumps({"step": step_losses, "epoch": epoch_losses}))
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(np.arange(1, len(step_losses) + 1) / steps_per_epoch, step_losses, lw=0.8,
            label="step")
    ax.plot(np.arange(1, len(epoch_losses) + 1), epoch_losses, "o-", label="epoch mean")
    ax.set(xlabel="epoch", ylabel="loss (normalised cost)", yscale="log",
           title="U-Net cost-map training")
    ax.legend()
    return save_figure(fig, out / "loss.png", dpi=100)


__all__ = ["Batch", "Loss", "StepCallback", "TrainConfig", "TrainResult", "batch_from_arrays",
           "loss_fn", "make_batch", "make_model", "train", "train_step", "write_losses"]
