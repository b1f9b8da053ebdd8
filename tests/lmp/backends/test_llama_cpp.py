"""The in-process GGUF backend with the real default model: code comes out, and few-shot prefixes
are evaluated once — then reused live, from memory, and from disk in a new backend."""

from __future__ import annotations

import ast
from dataclasses import replace
from pathlib import Path

import pytest

from voxposer.errors import ConfigError
from voxposer.lmp.backends import ChatMessage, LLMConfig, LLMRequest, make_backend
from voxposer.lmp.backends.cache import CachedBackend
from voxposer.lmp.backends.llama_cpp import LlamaCppBackend
from voxposer.lmp.backends.prefix_state import PrefixStateStore

SYSTEM = (
    "You write Python for a robot. Available: `move(obj, dx, dy, dz)` moves an object by the "
    "offsets in metres; axes: +x front, -x back, +y right, -y left, +z up, -z down. "
    "Answer with code only, no prose, no markdown fences."
)
EXAMPLES = [
    ("# Query: lift the cup by 5 cm.", "move('cup', 0, 0, 0.05)"),
    ("# Query: push the box 10 cm in the +x direction.", "move('box', 0.10, 0, 0)"),
    ("# Query: slide the plate 3 cm in the -y direction.", "move('plate', 0, -0.03, 0)"),
    ("# Query: lower the mug by 2 cm.", "move('mug', 0, 0, -0.02)"),
]


def messages(query: str, system: str = SYSTEM) -> tuple[ChatMessage, ...]:
    out = [ChatMessage("system", system)]
    for user, assistant in EXAMPLES:
        out += [ChatMessage("user", user), ChatMessage("assistant", assistant)]
    return (*out, ChatMessage("user", query))


def request(query: str, prefix_id: str | None = "mover", system: str = SYSTEM) -> LLMRequest:
    return LLMRequest(messages=messages(query, system), max_tokens=32, prefix_id=prefix_id)


def backend(model: Path, store_dir: Path) -> LlamaCppBackend:
    return LlamaCppBackend(model, n_ctx=2048, state_store=PrefixStateStore(store_dir))


def test_missing_gguf_is_a_config_error(tmp_path: Path) -> None:
    pytest.importorskip("llama_cpp")
    with pytest.raises(ConfigError, match="no such GGUF file"):
        LlamaCppBackend(tmp_path / "nope.gguf")


@pytest.mark.slow
def test_default_model_writes_code(default_model_path: Path, tmp_path: Path) -> None:
    llm = make_backend(LLMConfig(cache_dir=tmp_path, n_ctx=2048))
    assert isinstance(llm, CachedBackend) and llm.model == "qwen2.5-coder-1.5b-instruct-q4_k_m"
    req = LLMRequest(
        messages=(
            ChatMessage("system", "You are a Python coding assistant. Reply with code only."),
            ChatMessage("user", "Write a Python function add(a, b) that returns a + b."),
        ),
        max_tokens=64,
    )
    response = llm.complete(req)
    code = response.text.replace("```python", "").replace("```", "")
    assert "def add" in code
    ast.parse(code)  # valid Python
    assert response.completion_tokens > 0 and not response.cached
    again = llm.complete(req)
    assert again.cached and again.text == response.text
    llm.close()


@pytest.mark.slow
def test_prefix_is_evaluated_once_then_reused(default_model_path: Path, tmp_path: Path) -> None:
    store_dir = tmp_path / "states"
    llm = backend(default_model_path, store_dir)
    first = llm.complete(request("# Query: lift the bowl by 4 cm."))
    assert first.extra["prefix"] == "evaluated"
    n_prefix = first.extra["prefix_tokens"]
    assert isinstance(n_prefix, int) and n_prefix > 100
    assert "move('bowl'" in first.text and "0.04" in first.text
    assert len(list(store_dir.glob("*.kv"))) == 1

    second = llm.complete(request("# Query: push the can 6 cm in the +x direction."))
    assert second.extra["prefix"] == "live"
    assert "move('can', 0.06" in second.text

    # another program's prefix, then back: the first prefix is swapped in from memory
    other = llm.complete(request("# Query: lift the cup by 1 cm.", "other", SYSTEM + " Be exact."))
    assert other.extra["prefix"] == "evaluated"
    back = llm.complete(request("# Query: lift the bowl by 4 cm."))
    assert back.extra["prefix"] == "memory" and back.text == first.text

    # a self-correction retry extends the prefix: reused, not evaluated or saved again
    retry = LLMRequest(
        messages=(
            *messages("# Query: lift the bowl by 4 cm."),
            ChatMessage("assistant", "lift('bowl')"),
            ChatMessage("user", "Running your code failed: name 'lift' is not defined"),
        ),
        max_tokens=32,
        prefix_id="mover",
    )
    assert llm.complete(retry).extra["prefix"] in ("live", "memory")
    assert len(list(store_dir.glob("*.kv"))) == 2
    llm.close()

    # a new backend (as in a new process) restores the prefix from disk: same answer
    fresh = backend(default_model_path, store_dir)
    restored = fresh.complete(request("# Query: lift the bowl by 4 cm."))
    assert restored.extra["prefix"] == "disk"
    assert restored.text == first.text
    fresh.close()

    # warming ahead of time (e.g. in a setup step) restores without generating
    warmed = backend(default_model_path, store_dir)
    assert warmed.warm_prefix(request("# Query: anything"))["prefix"] == "disk"
    assert warmed.complete(request("# Query: lift the bowl by 4 cm.")).extra["prefix"] == "live"
    warmed.close()


@pytest.mark.slow
def test_requests_without_prefix_id_are_not_persisted(
    default_model_path: Path, tmp_path: Path
) -> None:
    llm = backend(default_model_path, tmp_path / "states")
    response = llm.complete(request("# Query: lift the cup by 2 cm.", prefix_id=None))
    assert response.extra["prefix"] == "none" and "move('cup'" in response.text
    assert not (tmp_path / "states").exists()
    llm.close()


def with_examples(query: str) -> LLMRequest:
    """A request whose prefix is followed by an example chosen for its query (as retrieval
    adds), marked as the query's context."""
    base = messages(query)
    chosen = (ChatMessage("user", "# Query: raise the jar by 7 cm."),
              ChatMessage("assistant", "move('jar', 0, 0, 0.07)"))
    full = (*base[:-1], *chosen, base[-1])
    return LLMRequest(messages=full, max_tokens=32, prefix_id="mover",
                      prefix_messages=len(base) - 1, context_messages=len(full) - 1)


@pytest.mark.slow
def test_query_context_is_evaluated_once_then_restored(
    default_model_path: Path, tmp_path: Path
) -> None:
    llm = backend(default_model_path, tmp_path / "states")
    first = llm.complete(with_examples("# Query: lift the bowl by 4 cm."))
    assert first.extra["context"] == "evaluated"
    assert first.extra["context_tokens"] > first.extra["prefix_tokens"]
    second = llm.complete(with_examples("# Query: push the can 6 cm in the +x direction."))
    assert second.extra["context"] == "live" and "move('can', 0.06" in second.text
    llm.complete(request("# Query: lift the cup by 1 cm.", "other", SYSTEM + " Be exact."))
    back = llm.complete(with_examples("# Query: lift the bowl by 4 cm."))
    assert back.extra["context"] == "memory" and back.text == first.text
    llm.close()

    # the same answers as a backend that keeps no context (every example evaluated each time)
    plain = LlamaCppBackend(default_model_path, n_ctx=2048, max_context_bytes=0)
    again = plain.complete(with_examples("# Query: push the can 6 cm in the +x direction."))
    assert "context" not in again.extra and again.text == second.text
    plain.close()


@pytest.mark.slow
def test_requests_generated_together_answer_as_one_after_another(
    default_model_path: Path, tmp_path: Path
) -> None:
    llm = backend(default_model_path, tmp_path / "states")
    requests = [request("# Query: lift the bowl by 4 cm."),
                with_examples("# Query: push the can 6 cm in the +x direction."),
                request("# Query: lift the cup by 1 cm.", "other", SYSTEM + " Be exact."),
                request("# Query: slide the plate 2 cm in the -y direction.")]
    alone = [llm.complete(r) for r in requests]
    together = llm.complete_many(requests)  # 3 together, then 1
    assert [r.text for r in together] == [r.text for r in alone]
    assert [r.extra["batched"] for r in together[:3]] == [3, 3, 3]
    assert "batched" not in together[3].extra or together[3].extra["batched"] == 1
    assert [r.completion_tokens for r in together] == [r.completion_tokens for r in alone]
    stopped = llm.complete_many([replace(requests[0], stop=("0.04",)), requests[2]])
    assert stopped[0].text == alone[0].text.split("0.04")[0] and stopped[1].text == alone[2].text
    llm.close()
