"""The one small interface every LLM backend implements.

A backend turns an :class:`LLMRequest` (a prompt as chat messages, or a raw completion prefix,
plus decoding settings) into an :class:`LLMResponse`. Backends: OpenAI-compatible endpoints,
in-process GGUF models (llama-cpp-python; the bundled default), and a replay backend that
serves recorded responses (a test double, never used silently).
"""

from __future__ import annotations

import hashlib
import json
from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from typing import Literal


@dataclass(frozen=True)
class ChatMessage:
    """One chat message; ``role`` is "system", "user" or "assistant"."""

    role: Literal["system", "user", "assistant"]
    content: str


@dataclass(frozen=True)
class LLMRequest:
    """Everything that determines a response (and so keys caches and recordings).

    Attributes:
        messages: the conversation; the last message is the query.
        temperature: sampling temperature (0 = greedy, the default for code).
        max_tokens: generation limit [tokens].
        stop: stop sequences.
        prefix_id: optional name of the reusable few-shot prefix (e.g. the LMP name); backends
            that can keep the prefix's state (KV cache) use it, others ignore it.
        prefix_messages: how many leading messages form that prefix (None: all but the last);
            examples chosen per query come after it.
        context_messages: how many leading messages form the query's context (the prefix and
            the examples chosen for it, not the query or a retry's turns); backends that keep
            model states may keep this one too. A hint only: it is not part of :meth:`key`.
    """

    messages: tuple[ChatMessage, ...]
    temperature: float = 0.0
    max_tokens: int = 512
    stop: tuple[str, ...] = ()
    prefix_id: str | None = None
    prefix_messages: int | None = None
    context_messages: int | None = None

    def key(self, backend: str, model: str) -> str:
        """Stable sha256 of backend + model + the full request (a ``prefix_messages`` of None
        is left out, so keys recorded before the field existed still match; the
        ``context_messages`` hint never enters it)."""
        request = asdict(self)
        del request["context_messages"]
        if self.prefix_messages is None:
            del request["prefix_messages"]
        payload = {"backend": backend, "model": model, "request": request}
        blob = json.dumps(payload, sort_keys=True, ensure_ascii=False).encode()
        return hashlib.sha256(blob).hexdigest()


@dataclass(frozen=True)
class LLMResponse:
    """A model's answer.

    Attributes:
        text: the generated text (without the prompt).
        model: the model that produced it.
        prompt_tokens: tokens in the prompt (0 if unknown).
        completion_tokens: generated tokens (0 if unknown).
        seconds: wall time of the call [s].
        cached: True when served from a cache or a recording rather than a model.
    """

    text: str
    model: str
    prompt_tokens: int = 0
    completion_tokens: int = 0
    seconds: float = 0.0
    cached: bool = False
    extra: dict[str, object] = field(default_factory=dict)


class LLMBackend(ABC):
    """An LLM that completes requests. Implementations must be safe to call repeatedly."""

    #: short backend name, e.g. "openai", "llama_cpp", "replay"
    name: str = "backend"

    @property
    @abstractmethod
    def model(self) -> str:
        """The model's name as reported in transcripts and cache keys."""

    @abstractmethod
    def complete(self, request: LLMRequest) -> LLMResponse:
        """Answer ``request``; raise :class:`voxposer.errors.LLMError` subclasses on failure."""

    def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        """Answer independent ``requests`` (in their order), together where the backend can:
        the same responses as :meth:`complete` one after another, which is what this default
        does. Wrappers pass the whole list on, so the innermost backend can batch it."""
        return [self.complete(r) for r in requests]

    def close(self) -> None:  # noqa: B027 - optional hook
        """Release resources (model memory, HTTP sessions)."""
