"""Operations on one llama-cpp-python context: chat template, token prefixes, KV state.

Kept apart from the backend (:mod:`voxposer.lmp.backends.llama_cpp`) so the policy there (which
prefix to evaluate, restore or keep) reads without the mechanics. ``llm`` is a
``llama_cpp.Llama``; ``lib`` the ``llama_cpp`` module (imported lazily: :func:`import_llama_cpp`).
"""

from __future__ import annotations

import ctypes
import logging
import sys
from typing import Any

import numpy as np

from voxposer.errors import LLMError
from voxposer.lmp.backends.base import ChatMessage
from voxposer.lmp.backends.config import configure_openmp, openmp_configured
from voxposer.lmp.backends.prefix_state import PrefixState

log = logging.getLogger(__name__)


def import_llama_cpp() -> Any:
    """The ``llama_cpp`` module, imported after OpenMP is configured for a shared CPU."""
    if "llama_cpp" not in sys.modules:
        configure_openmp()  # before libgomp loads with llama_cpp
    elif not openmp_configured():
        log.warning(
            "llama_cpp was imported before voxposer set OMP_WAIT_POLICY=PASSIVE; decoding may "
            "slow down by 10-30x when other processes compete for the CPU"
        )
    try:
        import llama_cpp
        import llama_cpp.llama_chat_format
    except ImportError as exc:  # pragma: no cover - depends on the install
        raise LLMError(
            "llama-cpp-python is not installed; run `bash scripts/setup.sh` "
            "(it installs the '[model]' extra) or pip install -e '.[model]'"
        ) from exc
    return llama_cpp


#: used only when a GGUF file carries no chat template
CHATML = (
    "{% for m in messages %}<|im_start|>{{ m['role'] }}\n{{ m['content'] }}<|im_end|>\n"
    "{% endfor %}{% if add_generation_prompt %}<|im_start|>assistant\n{% endif %}"
)


class ChatTemplate:
    """The model's own chat template (GGUF metadata ``tokenizer.chat_template``).

    Args:
        lib: the ``llama_cpp`` module.
        llm: a loaded model (for its metadata and special tokens).
    """

    def __init__(self, lib: Any, llm: Any) -> None:
        template = llm.metadata.get("tokenizer.chat_template") or CHATML
        eos = llm.detokenize([llm.token_eos()], special=True).decode("utf-8", "replace")
        bos_id = llm.token_bos()
        bos = (
            llm.detokenize([bos_id], special=True).decode("utf-8", "replace") if bos_id >= 0 else ""
        )
        fmt = lib.llama_chat_format.Jinja2ChatFormatter
        self._full = fmt(template, eos_token=eos, bos_token=bos, add_generation_prompt=True)
        self._prefix = fmt(template, eos_token=eos, bos_token=bos, add_generation_prompt=False)

    def render(self, messages: tuple[ChatMessage, ...],
               n_prefix: int | None = None) -> tuple[str, str | None]:
        """(the prompt with the assistant turn opened, the text of the first ``n_prefix``
        messages; None: all but the last).

        The second is None when that is no message or all of them, or when the template does
        not render those messages as a text prefix of the whole.
        """
        as_dicts = [{"role": m.role, "content": m.content} for m in messages]
        full = self._full(messages=as_dicts).prompt
        n = len(as_dicts) - 1 if n_prefix is None else n_prefix
        prefix = self._prefix(messages=as_dicts[:n]).prompt if 0 < n < len(as_dicts) else None
        if prefix is not None and not full.startswith(prefix):
            log.debug("chat template renders the prefix differently; no prefix reuse")
            prefix = None
        return full, prefix


def common_prefix(llm: Any, tokens: list[int] | np.ndarray) -> int:
    """How many leading ``tokens`` the context ``llm`` already holds."""
    n = min(int(llm.n_tokens), len(tokens))
    differ = np.flatnonzero(llm.input_ids[:n] != np.asarray(tokens[:n]))
    return int(differ[0]) if differ.size else n


def evaluate_exactly(llm: Any, tokens: list[int]) -> None:
    """Make ``llm`` hold exactly ``tokens``, reusing its longest common prefix with them."""
    keep = min(common_prefix(llm, tokens), len(tokens) - 1)
    llm.n_tokens = keep
    llm.eval(tokens[keep:])  # drops KV cells from ``keep`` on, then decodes the rest


def capture_state(lib: Any, llm: Any, key: str, n_tokens: int) -> PrefixState:
    """The context's state after its first ``n_tokens`` tokens (it must hold exactly those).

    Uses the runtime's raw state blob rather than ``Llama.save_state()``, which also copies a
    (n_batch × vocabulary) logits array: 311 MB for this model, useless for a prefix.
    """
    size = lib.llama_state_get_size(llm.ctx)
    buf = (ctypes.c_uint8 * size)()
    written = lib.llama_state_get_data(llm.ctx, buf, size)
    tokens = np.array(llm.input_ids[:n_tokens], dtype=np.int32)
    return PrefixState(key=key, tokens=tokens, data=bytes(memoryview(buf)[:written]))


def restore_state(lib: Any, llm: Any, state: PrefixState) -> None:
    """Load ``state`` into ``llm`` (as ``Llama.load_state()`` does, without the logits array)."""
    buf = (ctypes.c_uint8 * len(state.data)).from_buffer_copy(state.data)
    if lib.llama_state_set_data(llm.ctx, buf, len(state.data)) != len(state.data):
        raise LLMError(f"cannot restore prefix state {state.key[:12]}")
    llm.input_ids[: state.n_tokens] = state.tokens
    llm.n_tokens = state.n_tokens
    llm._requires_eval = True  # llama-cpp-python's flag: decode before sampling
