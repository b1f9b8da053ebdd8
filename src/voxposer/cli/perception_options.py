"""``--perception open-vocab --detector DIR --segmenter DIR``: the learned perception's options.

The open-vocabulary perceiver (:mod:`voxposer.perception.open_vocab`: OWLv2 boxes, SAM masks,
tracked between replans, fused across the cameras) needs two model directories the user gives;
nothing is downloaded. Checked before any work starts; the models load when the run builds its
perceiver.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, Final

from voxposer.errors import ConfigError

#: the ``--perception`` value of the learned open-vocabulary pipeline
OPEN_VOCAB: Final = "open-vocab"


def add_open_vocab_options(parser: argparse.ArgumentParser) -> None:
    """Register ``--detector``, ``--segmenter`` and ``--detector-threshold`` on ``parser``."""
    group = parser.add_argument_group("open-vocabulary perception (--perception open-vocab)")
    group.add_argument("--detector", type=str, default=None, metavar="DIR",
                       help="an Owlv2ForObjectDetection saved with its tokenizer (a directory, or "
                       "a model id already in the local Hugging Face cache)")
    group.add_argument("--segmenter", type=str, default=None, metavar="DIR",
                       help="a SamModel saved with save_pretrained (a directory or a cached id)")
    group.add_argument("--detector-threshold", type=float, default=0.1, metavar="SCORE",
                       help="the detector's least box score, in [0, 1] (default 0.1)")


def check_open_vocab_options(args: argparse.Namespace) -> None:
    """Refuse ``--perception open-vocab`` without both model folders, model folders without it,
    and a threshold outside [0, 1].

    Raises:
        ConfigError: naming the flag and what is allowed.
    """
    detector, segmenter = getattr(args, "detector", None), getattr(args, "segmenter", None)
    threshold = getattr(args, "detector_threshold", 0.1)
    if args.perception != OPEN_VOCAB:
        if detector is not None or segmenter is not None:
            raise ConfigError("--detector and --segmenter are for --perception open-vocab; got "
                              f"--perception {args.perception}")
        return
    for flag, value in (("--detector", detector), ("--segmenter", segmenter)):
        if value is None:
            raise ConfigError(f"--perception open-vocab needs {flag} DIR (a model saved on "
                              "this machine; nothing is downloaded)")
        _check_weights(flag, str(value))
    if not 0.0 <= threshold <= 1.0:
        raise ConfigError(f"--detector-threshold must be in [0, 1]; got {threshold!r}")


def _check_weights(flag: str, value: str) -> None:
    """A folder that exists, or something shaped like a model id ("owner/name", looked up in
    the local cache when the model loads); else ConfigError naming the flag and the value."""
    path = Path(value).expanduser()
    looks_like_id = value.count("/") == 1 and not value.startswith((".", "/", "~"))
    if path.is_file() or not (path.is_dir() or looks_like_id):
        raise ConfigError(f"{flag} {value!r}: no model directory there (give a folder written "
                          "by save_pretrained, or the id of a model in the local cache)")


def open_vocab_from_args(source: Any, grid: Any, args: argparse.Namespace) -> Any:
    """The open-vocabulary perceiver of ``args`` reading ``source`` on ``grid``.

    Raises:
        ConfigError: a folder holds no model of the expected class (naming both), or the
            ``vision`` extra is not installed.
    """
    from voxposer.perception.open_vocab import open_vocab_perceiver

    return open_vocab_perceiver(source, grid, args.detector, args.segmenter,
                                threshold=args.detector_threshold)


__all__ = ["OPEN_VOCAB", "add_open_vocab_options", "check_open_vocab_options",
           "open_vocab_from_args"]
