"""``voxposer train-unet``: train the language-conditioned cost U-Net (the "U-Net + MP"
baseline of paper Table 2) on a ``voxposer bench-data`` folder.

Writes to ``--out``: ``model.pt`` (latest) and ``checkpoints/epoch_NNN.pt`` after every epoch,
``losses.json`` and ``loss.png``. Needs the ``vision`` extra (torch).

Example::

    voxposer train-unet --data runs/unet-data --out runs/unet --epochs 20
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

from voxposer.cli.checks import check_int, check_out_dir
from voxposer.errors import ConfigError

console = Console(stderr=True)
ENCODINGS = ("topdown", "voxel")
LOSSES = ("mse", "smooth_l1")


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register ``train-unet`` on an ``argparse`` sub-parsers object."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "train-unet", help="train the U-Net + MP baseline's cost U-Net on bench-data output")
    p.add_argument("--data", type=Path, required=True, help="a voxposer bench-data folder")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    p.add_argument("--epochs", type=int, default=20, help="passes over the data (default 20)")
    p.add_argument("--batch-size", type=int, default=8, help="samples per step (default 8)")
    p.add_argument("--lr", type=float, default=1e-3, help="Adam learning rate (default 1e-3)")
    p.add_argument("--loss", default="mse", help=f"one of {', '.join(LOSSES)}")
    p.add_argument("--encoding", default="topdown", help=f"one of {', '.join(ENCODINGS)}")
    p.add_argument("--base-channels", type=int, default=32, help="U-Net width (default 32)")
    p.add_argument("--seed", type=int, default=0, help="seed of all randomness")
    p.add_argument("--threads", type=int, default=1, help="torch CPU threads (default 1)")
    p.set_defaults(func=run, check=check_args)
    return p


def check_args(args: argparse.Namespace) -> None:
    """Refuse bad values before any work (numbers, choices, a folder without a dataset)."""
    from voxposer.unet.dataset import MANIFEST

    check_int(args.epochs, "--epochs", 1)
    check_int(args.batch_size, "--batch-size", 1)
    check_int(args.base_channels, "--base-channels", 1)
    check_int(args.threads, "--threads", 1)
    check_int(args.seed, "--seed", 0)
    if not args.lr > 0:
        raise ConfigError(f"--lr must be > 0; got {args.lr!r}")
    if args.loss not in LOSSES:
        raise ConfigError(f"unknown --loss {args.loss!r}; choose one of: {', '.join(LOSSES)}")
    if args.encoding not in ENCODINGS:
        raise ConfigError(f"unknown --encoding {args.encoding!r}; choose one of: "
                          f"{', '.join(ENCODINGS)}")
    if not (args.data / MANIFEST).exists():
        raise ConfigError(f"--data {str(args.data)!r} holds no {MANIFEST}; write one with "
                          "voxposer bench-data")
    check_out_dir(args.out)


def run(args: argparse.Namespace) -> int:
    """Train with a progress bar; print the losses and where the model went."""
    from voxposer.unet.model import UNetConfig
    from voxposer.unet.train import TrainConfig, train

    config = TrainConfig(epochs=args.epochs, batch_size=args.batch_size, learning_rate=args.lr,
                         loss=args.loss, seed=args.seed, threads=args.threads,
                         model=UNetConfig(encoding=args.encoding,
                                          base_channels=args.base_channels))
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
               TimeElapsedColumn())
    start = time.perf_counter()
    with Progress(*columns, console=console) as bars:
        bar = bars.add_task("train-unet", total=None)

        def update(epoch: int, step: int, steps: int, loss: float) -> None:
            bars.update(bar, total=steps * args.epochs, completed=(epoch - 1) * steps + step,
                        description=f"epoch {epoch}/{args.epochs} loss {loss:.4g}")

        result = train(args.data, args.out, config, on_step=update)
    steps = len(result.step_losses)
    console.print(f"{steps} steps in {time.perf_counter() - start:.0f} s; epoch loss "
                  f"{result.epoch_losses[0]:.4g} → {result.epoch_losses[-1]:.4g}; wrote "
                  f"[bold]{result.checkpoint}[/bold] and {args.out / 'loss.png'}")
    return 0


__all__ = ["add_parser", "check_args"]
