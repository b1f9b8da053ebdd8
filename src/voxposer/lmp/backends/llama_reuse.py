"""Which evaluated state a llama.cpp context starts a request from (policy of
:class:`~voxposer.lmp.backends.llama_cpp.LlamaCppBackend`).

Two layers, each reused when it is already live in the context, else restored, else evaluated:

* the program's few-shot prefix, kept in memory by ``prefix_id`` and on disk by a
  :class:`PrefixStateStore` (a new process restores it instead of evaluating ~30 s);
* the query's context — that prefix and the examples chosen for the query — kept in memory
  (:class:`ContextStates`), so a later query given the same examples evaluates only itself.
"""

from __future__ import annotations

import logging
import time
from collections import OrderedDict
from typing import Any

import numpy as np

from voxposer.lmp.backends.context_states import ContextStates
from voxposer.lmp.backends.llama_context import (
    capture_state,
    common_prefix,
    evaluate_exactly,
    restore_state,
)
from voxposer.lmp.backends.prefix_state import PrefixState, PrefixStateStore, prefix_key

log = logging.getLogger(__name__)


class StateReuse:
    """Evaluated prefixes and query contexts of one model, and how to bring a context to them.

    Args:
        lib: the ``llama_cpp`` module.
        store_key: (model fingerprint, runtime version, n_ctx): what a saved state depends on.
        state_store: where prefix states persist across processes (None = memory only).
        max_memory_states: prefix states kept in memory.
        max_context_bytes: memory for query contexts [bytes]; 0 keeps none.
    """

    def __init__(self, lib: Any, store_key: tuple[str, str, int],
                 state_store: PrefixStateStore | None, max_memory_states: int,
                 max_context_bytes: int) -> None:
        self._lib = lib
        self._store_key = store_key
        self.state_store = state_store
        self.max_memory_states = max_memory_states
        self._states: OrderedDict[str, PrefixState] = OrderedDict()  # by prefix_id
        self.contexts = ContextStates(max_context_bytes)

    def _remember(self, prefix_id: str, state: PrefixState) -> None:
        self._states[prefix_id] = state
        self._states.move_to_end(prefix_id)
        while len(self._states) > self.max_memory_states:
            self._states.popitem(last=False)

    def _known_base(self, prefix_id: str, tokens: list[int]) -> PrefixState | None:
        """The remembered prefix state of ``prefix_id`` if ``tokens`` start with it (a
        self-correction retry extends the prefix: reused rather than saved again)."""
        state = self._states.get(prefix_id)
        if state is None or state.n_tokens > len(tokens):
            return None
        return state if np.array_equal(state.tokens, tokens[: state.n_tokens]) else None

    def prefix(self, llm: Any, prefix_id: str, text: str, tokens: list[int]) -> dict[str, object]:
        """Make ``llm`` hold the few-shot prefix ``text`` (its ``tokens``); how it was obtained
        ("live", "memory", "disk" or "evaluated"), its tokens and seconds."""
        start = time.perf_counter()
        base = self._known_base(prefix_id, tokens)
        source = "memory"
        if base is None:
            key = prefix_key(*self._store_key, text)
            base = self.state_store.load(key) if self.state_store is not None else None
            source = "disk"
            if base is None or not np.array_equal(base.tokens, tokens):
                source = "evaluated"
                evaluate_exactly(llm, tokens)
                base = capture_state(self._lib, llm, key, len(tokens))
                if self.state_store is not None:
                    self.state_store.save(base, prefix_id)
            self._remember(prefix_id, base)
        if common_prefix(llm, base.tokens) >= base.n_tokens:
            source = "live" if source == "memory" else source
        else:
            restore_state(self._lib, llm, base)
        seconds = time.perf_counter() - start
        log.info("prefix %s (%d tokens): %s in %.2f s", prefix_id, base.n_tokens, source, seconds)
        return {"prefix": source, "prefix_tokens": base.n_tokens, "prefix_seconds": seconds}

    def context(self, llm: Any, tokens: list[int]) -> dict[str, object]:
        """Make ``llm`` hold a query's context ``tokens`` (prefix and chosen examples): already
        live, restored from memory, or evaluated and kept."""
        n, start = len(tokens), time.perf_counter()
        have = common_prefix(llm, tokens)
        source = "live"
        if have < n and (state := self.contexts.longest(tokens, longer_than=have)) is not None:
            restore_state(self._lib, llm, state)
            have, source = state.n_tokens, "memory"
        if have < n:
            evaluate_exactly(llm, tokens)
            self.contexts.add(capture_state(self._lib, llm, "context", n))
            source = "evaluated"
        return {"context": source, "context_tokens": n,
                "context_seconds": time.perf_counter() - start}

    def clear(self) -> None:
        """Forget every state held in memory."""
        self._states.clear()
        self.contexts.clear()
