"""Model states at the end of a query's context (few-shot prefix + examples chosen for it).

A program's fixed few-shot prefix is evaluated once and swapped in by
:class:`~voxposer.lmp.backends.llama_cpp.LlamaCppBackend`. The examples retrieved per query come
after it and change with the query, but a small bank gives few distinct choices: over a benchmark
step the composer's 431 calls used 24 distinct example pairs. Evaluating a pair costs seconds
(~50 tokens/s on two cores); restoring its state costs tens of milliseconds. This module keeps
such states in memory, least recently used first out, within a byte budget (a state is ~28 KB
per token for the default model: ~60 MB for a 2,000-token context).
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from voxposer.errors import ConfigError
from voxposer.lmp.backends.prefix_state import PrefixState


def _token_key(tokens: np.ndarray) -> bytes:
    return np.asarray(tokens, dtype=np.int32).tobytes()


class ContextStates:
    """States of evaluated contexts, found by the longest one that starts a request's tokens.

    Args:
        max_bytes: memory kept [bytes]; 0 keeps nothing (every lookup misses).
    """

    def __init__(self, max_bytes: int) -> None:
        if max_bytes < 0:
            raise ConfigError(f"context state budget {max_bytes} bytes must be >= 0")
        self.max_bytes = int(max_bytes)
        self._states: OrderedDict[bytes, PrefixState] = OrderedDict()
        self._bytes = 0

    def __len__(self) -> int:
        return len(self._states)

    @property
    def nbytes(self) -> int:
        """Memory held [bytes]."""
        return self._bytes

    def longest(self, tokens: np.ndarray | list[int], longer_than: int = 0) -> PrefixState | None:
        """The kept state with the most tokens (more than ``longer_than``) that are a prefix of
        ``tokens``, marked as recently used; None when there is none."""
        tokens = np.asarray(tokens, dtype=np.int32)
        best: PrefixState | None = None
        for state in self._states.values():
            n = state.n_tokens
            if n <= longer_than or n > tokens.shape[0] or (best and n <= best.n_tokens):
                continue
            if np.array_equal(state.tokens, tokens[:n]):
                best = state
        if best is not None:
            self._states.move_to_end(_token_key(best.tokens))
        return best

    def add(self, state: PrefixState) -> bool:
        """Keep ``state`` (evicting the least recently used beyond the budget); False when it
        alone exceeds the budget and is not kept."""
        if state.nbytes > self.max_bytes:
            return False
        key = _token_key(state.tokens)
        old = self._states.pop(key, None)
        if old is not None:
            self._bytes -= old.nbytes
        self._states[key] = state
        self._bytes += state.nbytes
        while self._bytes > self.max_bytes:
            _, dropped = self._states.popitem(last=False)
            self._bytes -= dropped.nbytes
        return True

    def clear(self) -> None:
        """Forget every state."""
        self._states.clear()
        self._bytes = 0
