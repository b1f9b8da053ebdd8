"""``make_backend(config)``: the one place that turns an :class:`LLMConfig` into a backend.

Layering, outermost first: decoding overrides (config temperature / max_tokens) → response
cache → the backend itself, so cache keys see the request the model actually answers.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from voxposer.errors import ConfigError
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.backends.cache import CachedBackend, ResponseCache
from voxposer.lmp.backends.config import BACKEND_KINDS, LLMConfig, resolve_api_key

log = logging.getLogger(__name__)

RESPONSE_CACHE_FILE = "llm-responses.sqlite"
PREFIX_STATE_DIR = "prefix-states"


class DecodingOverrides(LLMBackend):
    """Applies a fixed temperature and/or generation limit to every request.

    Args:
        inner: the backend that answers.
        temperature: replaces each request's temperature when not None.
        max_tokens: replaces each request's max_tokens [tokens] when not None.
    """

    def __init__(
        self, inner: LLMBackend, temperature: float | None, max_tokens: int | None
    ) -> None:
        self.inner = inner
        self.name = inner.name
        self.temperature = temperature
        self.max_tokens = max_tokens

    @property
    def model(self) -> str:
        return self.inner.model

    def _override(self, request: LLMRequest) -> LLMRequest:
        return replace(
            request,
            temperature=request.temperature if self.temperature is None else self.temperature,
            max_tokens=request.max_tokens if self.max_tokens is None else self.max_tokens,
        )

    def complete(self, request: LLMRequest) -> LLMResponse:
        return self.inner.complete(self._override(request))

    def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        return self.inner.complete_many([self._override(r) for r in requests])

    def close(self) -> None:
        self.inner.close()


def _base_backend(config: LLMConfig) -> LLMBackend:
    if config.backend == "openai":
        from voxposer.lmp.backends.openai_compat import OpenAICompatBackend
        from voxposer.lmp.backends.retry import RetryPolicy

        return OpenAICompatBackend(
            model=config.model or "",
            base_url=config.base_url,
            api_key=resolve_api_key(config),
            timeout=config.timeout,
            retry=RetryPolicy(max_retries=config.max_retries, max_elapsed=config.total_timeout),
        )
    if config.backend == "replay":
        from voxposer.lmp.backends.replay import ReplayBackend

        if config.recordings_path is None:  # pragma: no cover - LLMConfig validates it
            raise ConfigError("backend='replay' needs recordings_path=<recordings file>")
        return ReplayBackend(config.recordings_path)
    if config.backend in ("default", "llama_cpp"):
        from voxposer.lmp.backends import default_model
        from voxposer.lmp.backends.llama_cpp import LlamaCppBackend
        from voxposer.lmp.backends.prefix_state import PrefixStateStore

        if config.backend == "default":
            spec = default_model.DEFAULT_MODEL
            path = default_model.require_installed(config.resolved_model_dir, spec)
            name, sha = spec.name, spec.sha256
        else:
            path, name, sha = Path(config.model or ""), None, None
        store = (
            PrefixStateStore(config.resolved_prefix_cache_dir / PREFIX_STATE_DIR)
            if config.prefix_cache
            else None
        )
        return LlamaCppBackend(
            path,
            model_name=name,
            n_ctx=config.n_ctx,
            n_threads=config.resolved_threads,
            state_store=store,
            model_sha256=sha,
            max_context_bytes=config.context_cache_mib << 20,
        )
    raise ConfigError(  # pragma: no cover - LLMConfig validates the kind
        f"backend={config.backend!r} is unknown; choose one of: {', '.join(BACKEND_KINDS)}"
    )


def make_backend(config: LLMConfig | None = None) -> LLMBackend:
    """The backend ``config`` describes (None = ``LLMConfig.from_env()``).

    Raises:
        ModelNotInstalledError: nothing configured and the default model is not installed.
        ConfigError: an invalid setting (e.g. a GGUF path that does not exist).
    """
    config = config if config is not None else LLMConfig.from_env()
    backend = _base_backend(config)
    log.info("LLM backend: %s (%s)", backend.name, backend.model)
    if config.cache and config.backend != "replay":
        cache = ResponseCache(config.resolved_cache_dir / RESPONSE_CACHE_FILE)
        backend = CachedBackend(backend, cache)
    if config.temperature is not None or config.max_tokens is not None:
        backend = DecodingOverrides(backend, config.temperature, config.max_tokens)
    return backend
