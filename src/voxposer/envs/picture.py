"""One PNG of the four camera views of a seeded scene, tiled in a grid."""

from __future__ import annotations

import logging
import math
from dataclasses import replace
from pathlib import Path

import imageio.v3 as iio
import numpy as np
from numpy.typing import NDArray

from voxposer.envs.config import WorldConfig
from voxposer.envs.layout import SceneLayout
from voxposer.envs.world import TabletopWorld

log = logging.getLogger(__name__)


def tile_images(images: list[NDArray[np.uint8]], columns: int = 2) -> NDArray[np.uint8]:
    """Tile equally sized RGB images, each (H, W, 3), row by row into one (rows*H, cols*W, 3)."""
    h, w, _ = images[0].shape
    rows = math.ceil(len(images) / columns)
    canvas = np.zeros((rows * h, columns * w, 3), dtype=np.uint8)
    for k, img in enumerate(images):
        r, c = divmod(k, columns)
        canvas[r * h:(r + 1) * h, c * w:(c + 1) * w] = img
    return canvas


def render_views(seed: int, out: Path, *, width: int = 640, height: int = 480,
                 config: WorldConfig | None = None, layout: SceneLayout | None = None
                 ) -> NDArray[np.uint8]:
    """Reset a world with ``numpy.random.default_rng(seed)``, render every camera, save a PNG.

    Args:
        seed: scene seed.
        out: PNG path (parent folders are created).
        width, height: size of each view [pixels].
        config: world configuration; by default the robot is drawn in full detail.

    Returns:
        The tiled image, shape (2*height, 2*width, 3).
    """
    cfg = config or WorldConfig()
    cfg = replace(cfg, cameras=replace(cfg.cameras, detailed_robot=True, width=width, height=height))
    world = TabletopWorld(cfg)
    try:
        world.reset(np.random.default_rng(seed), layout)
        views = [world.render(name, width, height) for name in world.camera_names]
    finally:
        world.close()
    image = tile_images(views)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    iio.imwrite(out, image)
    log.info("wrote %s (%d views, seed %d)", out, len(views), seed)
    return image
