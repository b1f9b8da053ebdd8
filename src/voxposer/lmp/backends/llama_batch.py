"""Greedy generation of several prompts at once in one llama.cpp context (batched decoding).

On a small CPU one generated token costs about as much for three sequences as for one: each
step reads the model's weights once, whatever the batch (measured: three 40-token generations
~1.5× faster together than one after another on two busy cores). :class:`BatchDecoder` owns a
second context on the backend's loaded model with a KV stream per sequence (a cache shared by
all, ``kv_unified``, made every sequence attend over every cell: slower than one at a time for
prompts of 2,000 tokens). Each prompt is evaluated in the backend's own context — where its few-shot
prefix and retrieved examples are restored, not evaluated again — up to its last token; that
sequence's KV cells are copied in (``llama_state_seq_get_data`` / ``_set_data``), and then every
sequence advances one token per step, each taking the most likely token (temperature 0).

``lib`` is the ``llama_cpp`` module; ``llm`` a ``llama_cpp.Llama``.
"""

from __future__ import annotations

import ctypes
import struct
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from voxposer.errors import LLMError

_HEADER = 8  # bytes before a sequence state's stream count


def sequence_state(lib: Any, llm: Any) -> bytes:
    """The KV cells of ``llm``'s (only) sequence, in the runtime's per-sequence format."""
    size = lib.llama_state_seq_get_size(llm.ctx, 0)
    buf = (ctypes.c_uint8 * size)()
    written = lib.llama_state_seq_get_data(llm.ctx, buf, size, 0)
    return bytes(memoryview(buf)[:written])


@dataclass(frozen=True)
class Prompted:
    """A sequence ready to generate.

    Attributes:
        state: its KV cells for every prompt token but the last (:func:`sequence_state`).
        last_token: the prompt's last token (decoded first, for the first logits).
        position: that token's position (the prompt's length - 1).
        max_tokens: generation limit [tokens].
        finished: called with the text generated so far; the generation ends when it returns the
            text to keep (a stop sequence found), else None.
    """

    state: bytes
    last_token: int
    position: int
    max_tokens: int
    finished: Callable[[str], str | None]


@dataclass(frozen=True)
class Generated:
    """What one sequence generated: its text, token count and why it ended."""

    text: str
    tokens: int
    finish_reason: str  # "stop" (end of turn or a stop sequence) or "length"


class BatchDecoder:
    """A context of ``n_seqs`` sequences sharing ``n_ctx`` KV cells, on ``llm``'s model."""

    def __init__(self, lib: Any, llm: Any, n_ctx: int, n_seqs: int, n_threads: int,
                 n_batch: int) -> None:
        self._lib = lib
        self._llm = llm
        params = lib.llama_context_default_params()
        for same in ("flash_attn_type", "type_k", "type_v", "swa_full"):  # the cells' layout
            setattr(params, same, getattr(llm.context_params, same))
        params.n_ctx, params.n_batch, params.n_ubatch = n_ctx, n_batch, n_batch
        params.n_seq_max, params.kv_unified = n_seqs, False
        params.n_threads, params.n_threads_batch = n_threads, n_threads
        self._ctx = lib.llama_init_from_model(llm.model, params)
        if not self._ctx:
            raise LLMError(f"cannot create a batch context of {n_ctx} tokens, {n_seqs} sequences")
        self.n_seqs = n_seqs
        self._vocab = lib.llama_model_get_vocab(llm.model)
        self._n_vocab = lib.llama_vocab_n_tokens(self._vocab)
        self._batch = lib.llama_batch_init(max(n_seqs, 1), 0, n_seqs)

    def generate(self, prompts: Sequence[Prompted]) -> list[Generated]:
        """Generate every prompt's continuation together (at most ``n_seqs`` prompts)."""
        if not 0 < len(prompts) <= self.n_seqs:
            raise LLMError(f"{len(prompts)} prompts for a batch of {self.n_seqs} sequences")
        lib = self._lib
        lib.llama_memory_clear(lib.llama_get_memory(self._ctx), True)
        for seq, p in enumerate(prompts):
            state = self._in_stream(p.state, seq)
            buf = (ctypes.c_uint8 * len(state)).from_buffer_copy(state)
            if lib.llama_state_seq_set_data(self._ctx, buf, len(state), seq) != len(state):
                raise LLMError("cannot load a prompt's state into the batch context")
        nxt = [p.last_token for p in prompts]
        pos = [p.position for p in prompts]
        tokens: list[list[int]] = [[] for _ in prompts]
        done: dict[int, Generated] = {}
        while len(done) < len(prompts):
            active = [s for s in range(len(prompts)) if s not in done]
            self._decode([(nxt[s], pos[s], s) for s in active])
            for row, s in enumerate(active):
                token = self._argmax(row)
                if lib.llama_vocab_is_eog(self._vocab, token):
                    done[s] = Generated(self._text(tokens[s]), len(tokens[s]), "stop")
                    continue
                tokens[s].append(token)
                nxt[s], pos[s] = token, pos[s] + 1
                text = self._text(tokens[s])
                if (kept := prompts[s].finished(text)) is not None:
                    done[s] = Generated(kept, len(tokens[s]), "stop")
                elif len(tokens[s]) >= prompts[s].max_tokens:
                    done[s] = Generated(text, len(tokens[s]), "length")
        return [done[s] for s in range(len(prompts))]

    def _in_stream(self, state: bytes, seq: int) -> bytes:
        """A one-stream sequence state (:func:`sequence_state`) as this context's ``n_seqs``
        streams with the cells in stream ``seq``. The pinned llama.cpp writes an 8-byte header,
        the stream count, then each stream's cell count and cells."""
        (streams,) = struct.unpack_from("<I", state, _HEADER)
        if streams != 1:
            raise LLMError(f"a sequence state of {streams} KV streams; expected 1 (another "
                           "llama.cpp state layout?)")
        empty = struct.pack("<I", 0)
        return b"".join((state[:_HEADER], struct.pack("<I", self.n_seqs), empty * seq,
                         state[_HEADER + 4:], empty * (self.n_seqs - seq - 1)))

    def _decode(self, entries: list[tuple[int, int, int]]) -> None:
        """One step: ``(token, position, sequence)`` each, every one asking for its logits."""
        batch = self._batch
        batch.n_tokens = len(entries)
        for i, (token, position, seq) in enumerate(entries):
            batch.token[i], batch.pos[i], batch.n_seq_id[i] = token, position, 1
            batch.seq_id[i][0], batch.logits[i] = seq, True
        if self._lib.llama_decode(self._ctx, batch) != 0:
            raise LLMError("batched decoding failed (the batch context is full)")

    def _argmax(self, row: int) -> int:
        logits = self._lib.llama_get_logits_ith(self._ctx, row)
        return int(np.ctypeslib.as_array(logits, shape=(self._n_vocab,)).argmax())

    def _text(self, tokens: list[int]) -> str:
        return self._llm.detokenize(tokens).decode("utf-8", errors="ignore")

    def close(self) -> None:
        """Free the context (the model stays loaded)."""
        if self._ctx:
            self._lib.llama_batch_free(self._batch)
            self._lib.llama_free(self._ctx)
            self._ctx = None
