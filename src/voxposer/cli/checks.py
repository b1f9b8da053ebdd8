"""Checks of command-line values, run before a command starts any work.

argparse checks types and choices; these check what the values mean (a seed is never negative,
a time limit is a positive number of seconds, an instruction says something). Every failure is a
:class:`~voxposer.errors.ConfigError` naming the option, the value and what is allowed; the CLI
prints it as one line and exits with status 2. :class:`OneLineParser` makes argparse's own
errors (an unknown option, ``--seed abc``) one line with the same status.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any, NoReturn
from urllib.parse import urlparse

from voxposer.errors import ConfigError

#: Largest image side ``voxposer render`` accepts [px].
MAX_IMAGE_PX = 4096


class OneLineParser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose usage errors are one line (and exit status 2)."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def check_int(value: int, option: str, minimum: int, maximum: int | None = None) -> int:
    """``value`` if ``minimum <= value <= maximum``; else ConfigError naming ``option``."""
    if value < minimum or (maximum is not None and value > maximum):
        allowed = f">= {minimum}" if maximum is None else f"in [{minimum}, {maximum}]"
        raise ConfigError(f"{option} must be an integer {allowed}; got {value}")
    return value


def check_seed(value: int | None, option: str = "--seed") -> int | None:
    """A scene/episode seed: None or an integer >= 0 (numpy's generators refuse negatives)."""
    return None if value is None else check_int(value, option, 0)


def check_seconds(value: float, option: str = "--max-time") -> float:
    """A time limit [s]: a finite number > 0."""
    if not (math.isfinite(value) and value > 0):
        raise ConfigError(f"{option} must be a finite number of seconds > 0; got {value:g}")
    return value


def check_text(value: str, what: str, example: str) -> str:
    """Text that says something: not empty, not only whitespace."""
    if not value.strip():
        raise ConfigError(f"the {what} is {'empty' if not value else 'only whitespace'} "
                          f"({value!r}); give one, e.g. {example!r}")
    return value


def check_out_dir(path: Path | None, option: str = "--out") -> Path | None:
    """An output folder: None, a folder, or a path that does not exist yet (not a file)."""
    if path is not None and path.exists() and not path.is_dir():
        raise ConfigError(f"{option} {str(path)!r} is a file; give a folder (existing or new)")
    return path


def check_out_file(path: Path | None, option: str) -> Path | None:
    """An output file: None, a file, or a path that does not exist yet (not a folder)."""
    if path is not None and path.is_dir():
        raise ConfigError(f"{option} {str(path)!r} is a folder; give a file path")
    return path


def check_llm_options(args: argparse.Namespace, backend: str | None) -> None:
    """The shared language-model options (:mod:`voxposer.cli.llm_options`) for ``backend``
    (None: from the environment): an http(s) ``--base-url``, a non-empty ``--model``, a
    ``--record`` file path, and every field the backend needs, from flags or ``VOXPOSER_LLM_*``.
    """
    from voxposer.cli.llm_options import llm_overrides
    from voxposer.lmp.backends.config import LLMConfig

    if args.base_url is not None:
        url = urlparse(args.base_url)
        if url.scheme not in ("http", "https") or not url.netloc:
            raise ConfigError(f"--base-url must be an http:// or https:// URL with a host, e.g. "
                              f"'http://127.0.0.1:8080/v1'; got {args.base_url!r}")
    if args.model is not None and not args.model.strip():
        raise ConfigError(f"--model must name a model (a GGUF path or a model name); got "
                          f"{args.model!r}")
    check_out_file(getattr(args, "record", None), "--record")
    overrides: dict[str, Any] = llm_overrides(args)
    if backend is not None:
        overrides["backend"] = backend
    try:
        LLMConfig.from_env(**overrides)
    except ConfigError as err:
        raise ConfigError(f"language model options: {err} (flags: --llm, --model, --base-url, "
                          "--recordings; or the VOXPOSER_LLM_* variables)") from err


__all__ = ["MAX_IMAGE_PX", "OneLineParser", "check_int", "check_llm_options", "check_out_dir",
           "check_out_file", "check_seconds", "check_seed", "check_text"]
