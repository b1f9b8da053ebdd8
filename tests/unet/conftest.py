"""A tiny synthetic cost-map dataset: the cost is the distance to a voxel the instruction names
(so the model must read both the observation and the instruction)."""

from __future__ import annotations

import numpy as np
import pytest

from voxposer.unet.vocabulary import Vocabulary

torch = pytest.importorskip("torch")
torch.set_num_threads(1)

GRID = (12, 12, 8)
INSTRUCTIONS = ("move to the red block", "move to the blue block")


def tiny_samples(n: int = 4, seed: int = 0) -> dict[str, np.ndarray]:
    """``n`` samples on :data:`GRID`: two blocks (red, blue) on a table, cost = normalised
    distance to the block the instruction names."""
    rng = np.random.default_rng(seed)
    occ = np.zeros((n, *GRID), dtype=np.uint8)
    colour = np.zeros((n, *GRID, 3), dtype=np.uint8)
    cost = np.zeros((n, *GRID), dtype=np.float32)
    ii, jj, kk = np.meshgrid(*(np.arange(s) for s in GRID), indexing="ij")
    instructions = []
    for b in range(n):
        occ[b, :, :, 0] = 1
        colour[b, :, :, 0] = (120, 120, 120)
        blocks = rng.choice(np.arange(2, 10), size=(2, 2), replace=False)
        for (x, y), rgb in zip(blocks, ((255, 0, 0), (0, 0, 255)), strict=True):
            occ[b, x, y, 1:3] = 1
            colour[b, x, y, 1:3] = rgb
        which = b % 2
        x, y = blocks[which]
        d = np.sqrt((ii - x) ** 2 + (jj - y) ** 2 + (kk - 3) ** 2)
        cost[b] = 3.0 * d / d.max()
        instructions.append(INSTRUCTIONS[which])
    return {"occupancy": occ, "colour": colour, "cost": cost, "instruction": instructions}


@pytest.fixture
def samples() -> dict[str, np.ndarray]:
    return tiny_samples()


@pytest.fixture
def vocabulary() -> Vocabulary:
    return Vocabulary.build(INSTRUCTIONS)
