"""``voxposer render``: save the four camera views of a seeded scene as one PNG, or (with
``--save-frames DIR``) as a folder of recorded RGB-D frames (:mod:`voxposer.perception.frames`)
that ``voxposer run --frames DIR --robot none`` plans on."""

from __future__ import annotations

import argparse
import logging
from pathlib import Path
from typing import TYPE_CHECKING, Any

from voxposer.cli.checks import (
    MAX_IMAGE_PX,
    check_int,
    check_out_dir,
    check_out_file,
    check_seed,
)
from voxposer.errors import ConfigError, VoxPoserError

if TYPE_CHECKING:
    from voxposer.envs import TabletopWorld

log = logging.getLogger(__name__)


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register the ``render`` sub-command on an ``argparse`` sub-parsers object."""
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "render", help="render the four camera views of a seeded tabletop scene to one PNG")
    parser.add_argument("--seed", type=int, default=0, help="scene seed (default 0)")
    parser.add_argument("--out", type=Path, default=None,
                        help="output PNG path (default views.png; none with --save-frames)")
    parser.add_argument("--width", type=int, default=640, help="width of each view [px]")
    parser.add_argument("--height", type=int, default=480, help="height of each view [px]")
    parser.add_argument("--save-frames", type=Path, default=None, metavar="DIR",
                        help="write the views as recorded frames: per camera colour PNG, 16-bit "
                        "depth PNG [mm], and frames.json (calibration, robot state)")
    parser.add_argument("--with-labels", action="store_true",
                        help="with --save-frames: also the ground-truth segmentation (a real "
                        "camera has none)")
    parser.set_defaults(func=run, check=check_args)
    return parser


def check_args(args: argparse.Namespace) -> None:
    """Refuse a negative ``--seed``, an image side outside [1, MAX_IMAGE_PX] px, an ``--out``
    that is a folder, a ``--save-frames`` that is a file and ``--with-labels`` without it, before
    the scene is built."""
    check_seed(args.seed)
    check_int(args.width, "--width", 1, MAX_IMAGE_PX)
    check_int(args.height, "--height", 1, MAX_IMAGE_PX)
    check_out_file(args.out, "--out")
    check_out_dir(args.save_frames, "--save-frames")
    if args.with_labels and args.save_frames is None:
        raise ConfigError("--with-labels writes the label channel of --save-frames DIR; add "
                          "--save-frames")


def run(args: argparse.Namespace) -> int:
    """Render and save; returns the process exit code (0 on success, 1 on a VoxPoserError)."""
    from voxposer.envs.picture import render_views

    out = args.out if args.out is not None or args.save_frames is not None else Path("views.png")
    try:
        if out is not None:
            render_views(args.seed, out, width=args.width, height=args.height)
            log.info("saved %s", out)
        if args.save_frames is not None:
            path = save_scene_frames(args.seed, args.save_frames, args.width, args.height,
                                     labels=args.with_labels)
            log.info("saved %s", path)
    except VoxPoserError as err:
        log.error("render failed: %s", err)
        return 1
    return 0


def scene_world(seed: int, width: int, height: int) -> TabletopWorld:
    """The world ``voxposer render`` shows: reset with ``numpy.random.default_rng(seed)``, the
    robot drawn in full detail, cameras of ``width`` x ``height`` px (the caller closes it)."""
    from dataclasses import replace

    import numpy as np

    from voxposer.envs import TabletopWorld, WorldConfig

    cfg = WorldConfig()
    cfg = replace(cfg, cameras=replace(cfg.cameras, detailed_robot=True, width=width,
                                       height=height))
    world = TabletopWorld(cfg)
    world.reset(np.random.default_rng(seed))
    return world


def save_scene_frames(seed: int, directory: Path, width: int, height: int, *,
                      labels: bool = False) -> Path:
    """Save the views of :func:`scene_world` as recorded frames in ``directory``
    (:func:`voxposer.perception.frames.save_frames`); returns the ``frames.json`` written."""
    from voxposer.perception.frames import save_frames

    world = scene_world(seed, width, height)
    try:
        return save_frames(world.observe(), directory, labels=labels,
                           gripper_opening_m=world.gripper_opening())
    finally:
        world.close()
