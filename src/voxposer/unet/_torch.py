"""torch for the U-Net modules, or a ConfigError saying which extra installs it."""

from __future__ import annotations

from voxposer.errors import ConfigError

try:
    import torch as torch
    from torch import nn as nn
except ImportError as err:  # pragma: no cover - the vision extra is installed in CI
    raise ConfigError(
        "the U-Net baseline needs torch, which is not installed; install the 'vision' extra "
        "(pip install 'voxposer[vision]')") from err


def generator_from(rng_seed: int) -> torch.Generator:
    """A CPU torch generator seeded with ``rng_seed`` (drawn from a numpy Generator)."""
    gen = torch.Generator()
    gen.manual_seed(int(rng_seed))
    return gen


__all__ = ["generator_from", "nn", "torch"]
