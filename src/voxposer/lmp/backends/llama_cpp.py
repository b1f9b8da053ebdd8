"""A local GGUF model in-process (llama-cpp-python), with few-shot prefix reuse.

Prompts are rendered with the model's own chat template (from the GGUF metadata). The prefix of a
request is everything before its last message (the query): the program's header and examples.
It is evaluated once; its KV state is then

* kept live in the context (llama-cpp-python reuses the longest common token prefix, so the next
  query with the same prefix pays only for its own tokens),
* kept in memory, so switching between programs restores it in milliseconds, and
* (for requests with a ``prefix_id``) saved to disk by a :class:`PrefixStateStore`, so a new
  process skips the evaluation too.

The examples chosen per query (a request's ``context_messages``) extend that prefix; the state at
their end is kept in memory too, so a later query given the same examples evaluates only itself
(:mod:`voxposer.lmp.backends.llama_reuse`). :meth:`LlamaCppBackend.complete_many` generates
several greedy requests together (:mod:`voxposer.lmp.backends.llama_batch`).

By default one context serves all programs and swaps prefix states (``max_contexts=1``, ~1 s per
switch including the query): each extra context costs ~0.8 GB of private memory (measured:
repacked weights, KV cache, compute buffers) for no speed-up on a small CPU machine.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any

from voxposer.errors import ConfigError, LLMError
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.backends.config import available_cores
from voxposer.lmp.backends.llama_batch import BatchDecoder, Prompted, sequence_state
from voxposer.lmp.backends.llama_context import (
    ChatTemplate,
    common_prefix,
    evaluate_exactly,
    import_llama_cpp,
)
from voxposer.lmp.backends.llama_reuse import StateReuse
from voxposer.lmp.backends.prefix_state import PrefixStateStore, file_fingerprint

log = logging.getLogger(__name__)

MIN_PREFIX_TOKENS = 32  # shorter prefixes are not worth saving


@dataclass
class _Slot:
    """One llama.cpp context and when it was last used."""

    llm: Any
    used: float = field(default_factory=time.monotonic)


class LlamaCppBackend(LLMBackend):
    """Chat completions from a GGUF model file, evaluated in this process.

    Args:
        model_path: the .gguf file.
        model_name: name reported in responses and cache keys (default: the file's stem).
        n_ctx: context window [tokens].
        n_threads: CPU threads; None = the cores available.
        n_batch: prompt evaluation batch [tokens].
        state_store: where prefix states persist across processes (None = memory only).
        model_sha256: the file's known sha256 (keys saved states; else a cheap fingerprint).
        max_contexts: live contexts kept (each ~0.8 GB); prefixes beyond swap state.
        max_memory_states: evaluated prefix states kept in memory for swapping.
        max_context_bytes: memory for states at the end of queries' contexts (few-shot prefix
            plus the examples chosen per query) [bytes]; 0 keeps none.
        max_batch: requests generated together by :meth:`complete_many` (a second context of
            ``max_batch`` × ``n_ctx`` KV cells, ~28 KB each for the default model); 1: none.
    """

    name = "llama_cpp"

    def __init__(
        self,
        model_path: Path,
        *,
        model_name: str | None = None,
        n_ctx: int = 4096,
        n_threads: int | None = None,
        n_batch: int = 512,
        state_store: PrefixStateStore | None = None,
        model_sha256: str | None = None,
        max_contexts: int = 1,
        max_memory_states: int = 16,
        max_context_bytes: int = 768 << 20,
        max_batch: int = 3,
    ) -> None:
        self.model_path = Path(model_path)
        if not self.model_path.is_file():
            raise ConfigError(f"model={str(self.model_path)!r}: no such GGUF file")
        if n_ctx < 512:
            raise ConfigError(f"n_ctx={n_ctx} tokens must be >= 512")
        if max_contexts < 1:
            raise ConfigError(f"max_contexts={max_contexts} must be >= 1")
        self._lib = import_llama_cpp()
        self._model_name = model_name or self.model_path.stem
        self.n_ctx = n_ctx
        self.n_threads = n_threads or available_cores()
        self.n_batch = n_batch
        self.max_contexts = max_contexts
        store_key = (file_fingerprint(self.model_path, model_sha256),
                     f"llama-cpp-python-{self._lib.__version__}", n_ctx)
        self._reuse = StateReuse(self._lib, store_key, state_store, max_memory_states,
                                 max_context_bytes)
        self._slots: list[_Slot] = []
        self.max_batch = max_batch
        self._batch: BatchDecoder | None = None
        self._lock = threading.RLock()
        self._template: ChatTemplate | None = None

    @property
    def model(self) -> str:
        return self._model_name

    # ----------------------------------------------------------------------------- contexts

    def _new_llama(self) -> Any:
        log.info("loading %s (n_ctx=%d, threads=%d)", self.model_path, self.n_ctx, self.n_threads)
        try:
            return self._lib.Llama(
                model_path=str(self.model_path),
                n_ctx=self.n_ctx,
                n_batch=self.n_batch,
                n_threads=self.n_threads,
                n_threads_batch=self.n_threads,
                use_mmap=True,
                logits_all=False,
                verbose=False,
            )
        except (ValueError, RuntimeError) as exc:
            raise LLMError(f"cannot load GGUF model {self.model_path}: {exc}") from exc

    def _pick_slot(self, tokens: list[int]) -> _Slot:
        """The context sharing the longest prefix with ``tokens``, else a new or the oldest one."""
        best = max(self._slots, key=lambda s: common_prefix(s.llm, tokens), default=None)
        if best is not None and common_prefix(best.llm, tokens) > 0:
            return best
        if len(self._slots) < self.max_contexts:
            self._slots.append(_Slot(self._new_llama()))
            return self._slots[-1]
        return min(self._slots, key=lambda s: s.used)

    def _first_llm(self) -> Any:
        if not self._slots:
            self._slots.append(_Slot(self._new_llama()))
        return self._slots[0].llm

    # ----------------------------------------------------------------------------- prompts

    def _render(self, request: LLMRequest) -> tuple[str, str | None]:
        """(full prompt with the assistant turn opened, the text of the request's prefix
        messages)."""
        if self._template is None:
            self._template = ChatTemplate(self._lib, self._first_llm())
        return self._template.render(request.messages, request.prefix_messages)

    def _tokenize(self, text: str) -> list[int]:
        return list(self._first_llm().tokenize(text.encode("utf-8"), add_bos=True, special=True))

    # ----------------------------------------------------------------------------- states

    def _prepare(
        self, prefix_id: str | None, prefix: str | None, full: list[int]
    ) -> tuple[_Slot, dict[str, object]]:
        """A context holding the request's few-shot prefix (evaluated, restored or live)."""
        slot = self._pick_slot(full)
        if prefix_id is None or prefix is None:
            return slot, {"prefix": "none"}
        tokens = self._tokenize(prefix)
        if len(tokens) < MIN_PREFIX_TOKENS or len(tokens) >= self.n_ctx - 16:
            return slot, {"prefix": "none"}
        return slot, self._reuse.prefix(slot.llm, prefix_id, prefix, tokens)

    def _resume_context(self, slot: _Slot, request: LLMRequest,
                        full: list[int]) -> dict[str, object]:
        """Bring ``slot`` to the end of the request's context (its prefix and the examples chosen
        for its query), when the request marks one."""
        if request.context_messages is None or request.prefix_id is None \
                or self._reuse.contexts.max_bytes == 0 or self._template is None:
            return {}
        _, text = self._template.render(request.messages, request.context_messages)
        if text is None:
            return {}
        tokens = self._tokenize(text)
        if len(tokens) >= len(full) or tokens != full[:len(tokens)]:
            return {}
        return self._reuse.context(slot.llm, tokens)

    # ----------------------------------------------------------------------------- requests

    def warm_prefix(self, request: LLMRequest) -> dict[str, object]:
        """Evaluate (or restore) and persist ``request``'s prefix without generating.

        Lets a setup step pay the prefix evaluation ahead of the first real query. Returns how the
        prefix was obtained ("evaluated", "disk", "memory", "live" or "none").
        """
        with self._lock:
            full, prefix = self._render(request)
            _, info = self._prepare(request.prefix_id, prefix, self._tokenize(full))
            return info

    def _staged(self, request: LLMRequest) -> tuple[_Slot, list[int], int, dict[str, object]]:
        """(a context holding the request's prefix and examples, the prompt's tokens, the
        generation limit, how the prefix and examples were obtained)."""
        if not request.messages:
            raise LLMError("request has no messages")
        full, prefix = self._render(request)
        tokens = self._tokenize(full)
        room = self.n_ctx - len(tokens)
        if room < 16:
            raise LLMError(
                f"prompt of {len(tokens)} tokens does not fit n_ctx={self.n_ctx} of "
                f"{self.model}; raise n_ctx (VOXPOSER_LLM_N_CTX) or shorten the prompt"
            )
        slot, info = self._prepare(request.prefix_id, prefix, tokens)
        info.update(self._resume_context(slot, request, tokens))
        slot.used = time.monotonic()
        return slot, tokens, min(request.max_tokens, room), info

    def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        """Greedy requests generated together, ``max_batch`` at a time (:mod:`llama_batch`);
        others, or a single one, one after another."""
        if len(requests) < 2 or self.max_batch < 2 or any(r.temperature > 0 for r in requests):
            return super().complete_many(requests)
        out: list[LLMResponse] = []
        with self._lock:
            for k in range(0, len(requests), self.max_batch):
                chunk = requests[k:k + self.max_batch]
                try:
                    out += self._together(chunk)
                except LLMError as exc:  # e.g. a runtime whose state layout differs
                    log.warning("generating %d requests together failed (%s); one after "
                                "another from now on", len(chunk), exc)
                    self.max_batch = 1
                    out += [self.complete(r) for r in chunk]
        return out

    def _together(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        start = time.perf_counter()
        staged = []
        for request in requests:
            slot, tokens, max_tokens, info = self._staged(request)
            evaluate_exactly(slot.llm, tokens[:-1])
            staged.append((tokens, info, Prompted(
                sequence_state(self._lib, slot.llm), tokens[-1], len(tokens) - 1, max_tokens,
                partial(_cut_at_stop, stops=request.stop))))
        if self._batch is None:
            self._batch = BatchDecoder(self._lib, self._first_llm(), self.n_ctx * self.max_batch,
                                       self.max_batch, self.n_threads, self.n_batch)
        generated = self._batch.generate([p for _, _, p in staged])
        share = (time.perf_counter() - start) / len(requests)  # the call's time, split evenly
        return [LLMResponse(text=g.text, model=self._model_name, prompt_tokens=len(tokens),
                            completion_tokens=g.tokens, seconds=share,
                            extra={**info, "finish_reason": g.finish_reason,
                                   "batched": len(requests)})
                for (tokens, info, _), g in zip(staged, generated, strict=True)]

    def complete(self, request: LLMRequest) -> LLMResponse:
        with self._lock:
            start = time.perf_counter()
            slot, tokens, max_tokens, info = self._staged(request)
            out = slot.llm.create_completion(
                prompt=tokens,
                max_tokens=max_tokens,
                temperature=request.temperature,
                stop=list(request.stop) or None,
            )
            choice = out["choices"][0]
            usage = out.get("usage") or {}
            return LLMResponse(
                text=choice["text"],
                model=self._model_name,
                prompt_tokens=int(usage.get("prompt_tokens", len(tokens))),
                completion_tokens=int(usage.get("completion_tokens", 0)),
                seconds=time.perf_counter() - start,
                extra={**info, "finish_reason": choice.get("finish_reason")},
            )

    def close(self) -> None:
        with self._lock:
            for slot in self._slots:
                slot.llm.close()
            if self._batch is not None:
                self._batch.close()
                self._batch = None
            self._slots.clear()
            self._reuse.clear()


def _cut_at_stop(text: str, stops: tuple[str, ...]) -> str | None:
    """``text`` up to its first stop sequence, or None when it holds none."""
    found = [i for i in (text.find(s) for s in stops) if i >= 0]
    return text[:min(found)] if found else None
