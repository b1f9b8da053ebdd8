"""Command-line flags choosing the LLM backend, shared by ``voxposer lmp`` and the benchmark."""

from __future__ import annotations

import argparse
from pathlib import Path

from voxposer.lmp.backends.base import LLMBackend
from voxposer.lmp.backends.replay import RecordingBackend


def add_backend_args(parser: argparse.ArgumentParser) -> None:
    """``--backend``, ``--model``, ``--base-url``, ``--recordings``, ``--record``."""
    group = parser.add_argument_group("language model")
    group.add_argument("--backend", choices=("default", "llama_cpp", "openai", "replay"),
                       default=None, help="LLM backend (default: VOXPOSER_LLM_BACKEND, else the "
                       "bundled local model)")
    group.add_argument("--model", default=None, help="GGUF path (llama_cpp) or model name (openai)")
    group.add_argument("--base-url", default=None, help="OpenAI-compatible endpoint URL")
    group.add_argument("--recordings", type=Path, default=None,
                       help="recordings file for --backend replay (a test double)")
    group.add_argument("--record", type=Path, default=None,
                       help="append every LLM exchange to this recordings file (JSONL)")


def backend_from_args(args: argparse.Namespace) -> LLMBackend:
    """Build the backend the flags describe (through ``make_backend``), optionally recording."""
    from voxposer.lmp.backends.config import LLMConfig
    from voxposer.lmp.backends.factory import make_backend

    overrides = {key: value for key, value in (
        ("backend", args.backend), ("model", args.model), ("base_url", args.base_url),
        ("recordings_path", args.recordings)) if value is not None}
    backend = make_backend(LLMConfig.from_env(**overrides))
    if args.record is not None:
        backend = RecordingBackend(backend, args.record)
    return backend
