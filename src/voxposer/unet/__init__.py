"""The "U-Net + MP" baseline of the paper's Table 2 (after Sharma et al. [50]): a
language-conditioned U-Net maps an observation and an instruction to the planner's cost map.

Modules, one concept each:

* :mod:`~voxposer.unet.encoding` — the observation at the planner's cost grid (NumPy only).
* :mod:`~voxposer.unet.vocabulary` — word tokens of instructions, with an unknown token (no torch).
* :mod:`~voxposer.unet.instruction` — a learned, mean-pooled word embedding (torch).
* :mod:`~voxposer.unet.model` — the FiLM-conditioned U-Net (torch).
* :mod:`~voxposer.unet.checkpoint` — save/load with config, grid shape and vocabulary (torch).
* :mod:`~voxposer.unet.train` — the training loop (torch).
* :mod:`~voxposer.unet.predict` — a checkpoint's cost map for the planner (torch).

Importing this package imports no torch: the torch modules raise
:class:`~voxposer.errors.ConfigError` naming the ``vision`` extra when torch is missing.
"""

from __future__ import annotations
