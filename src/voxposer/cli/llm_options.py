"""The language-model options every command shares (``run``, ``bench``, ``lmp``, the LMP
accuracy benchmark): one definition of ``--llm``, ``--model``, ``--base-url``,
``--recordings`` and ``--record``."""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from voxposer.lmp.backends.base import LLMBackend
from voxposer.lmp.backends.replay import RecordingBackend

#: The LLM backends (``LLMConfig.backend``); ``replay`` serves recordings (a test double).
BACKENDS = ("default", "llama_cpp", "openai", "replay")


def add_llm_options(parser: argparse.ArgumentParser, *, extra_choices: Sequence[str] = (),
                    default: str | None = None, extra_help: str = "", record: bool = True
                    ) -> None:
    """Add the shared options to ``parser``.

    Args:
        extra_choices: further ``--llm`` values the command handles itself (the benchmark's
            reference programs).
        default: the ``--llm`` default (None: ``VOXPOSER_LLM_BACKEND``, else the bundled model).
        extra_help: appended to ``--llm``'s help.
        record: offer ``--record`` (commands that build their backend in this process).
    """
    group = parser.add_argument_group("language model")
    group.add_argument("--llm", "--backend", dest="llm", choices=(*BACKENDS, *extra_choices),
                       default=default, help="LLM backend (default: VOXPOSER_LLM_BACKEND, else "
                       "the bundled local model)" + extra_help)
    group.add_argument("--model", default=None,
                       help="GGUF path (llama_cpp) or model name (openai)")
    group.add_argument("--base-url", default=None, help="OpenAI-compatible endpoint URL")
    group.add_argument("--recordings", type=Path, default=None,
                       help="recorded responses for --llm replay (a test double)")
    if record:
        group.add_argument("--record", type=Path, default=None,
                           help="append every LLM exchange to this recordings file (JSONL)")


def llm_overrides(args: argparse.Namespace) -> dict[str, Any]:
    """The ``LLMConfig`` fields the options set (model, endpoint, recordings; not the backend)."""
    return {key: value for key, value in (
        ("model", args.model), ("base_url", args.base_url),
        ("recordings_path", args.recordings)) if value is not None}


def backend_from_args(args: argparse.Namespace) -> LLMBackend:
    """Build the backend the options describe (through ``make_backend``), optionally recording
    every exchange."""
    from voxposer.lmp.backends.config import LLMConfig
    from voxposer.lmp.backends.factory import make_backend

    overrides = llm_overrides(args)
    if args.llm is not None:
        overrides["backend"] = args.llm
    backend = make_backend(LLMConfig.from_env(**overrides))
    if getattr(args, "record", None) is not None:
        backend = RecordingBackend(backend, args.record)
    return backend


__all__ = ["BACKENDS", "add_llm_options", "backend_from_args", "llm_overrides"]
