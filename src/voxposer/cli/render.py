"""``voxposer render``: save the four camera views of a seeded scene as one PNG."""

from __future__ import annotations

import argparse
import logging
from pathlib import Path
from typing import Any

from voxposer.cli.checks import MAX_IMAGE_PX, check_int, check_out_file, check_seed
from voxposer.errors import VoxPoserError

log = logging.getLogger(__name__)


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register the ``render`` sub-command on an ``argparse`` sub-parsers object."""
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "render", help="render the four camera views of a seeded tabletop scene to one PNG")
    parser.add_argument("--seed", type=int, default=0, help="scene seed (default 0)")
    parser.add_argument("--out", type=Path, default=Path("views.png"), help="output PNG path")
    parser.add_argument("--width", type=int, default=640, help="width of each view [px]")
    parser.add_argument("--height", type=int, default=480, help="height of each view [px]")
    parser.set_defaults(func=run, check=check_args)
    return parser


def check_args(args: argparse.Namespace) -> None:
    """Refuse a negative ``--seed``, an image side outside [1, MAX_IMAGE_PX] px and an ``--out``
    that is a folder, before the scene is built."""
    check_seed(args.seed)
    check_int(args.width, "--width", 1, MAX_IMAGE_PX)
    check_int(args.height, "--height", 1, MAX_IMAGE_PX)
    check_out_file(args.out, "--out")


def run(args: argparse.Namespace) -> int:
    """Render and save; returns the process exit code (0 on success, 1 on a VoxPoserError)."""
    from voxposer.envs.picture import render_views

    try:
        render_views(args.seed, args.out, width=args.width, height=args.height)
    except VoxPoserError as err:
        log.error("render failed: %s", err)
        return 1
    log.info("saved %s", args.out)
    return 0
