"""LLM backends: one interface (:class:`LLMBackend`), several ways to answer.

* ``default`` — the bundled Qwen2.5-Coder-1.5B-Instruct Q4_K_M, in-process (``default_model``)
* ``llama_cpp`` — any GGUF file, in-process, with few-shot prefix reuse (``llama_cpp``)
* ``openai`` — any OpenAI-compatible endpoint (``openai_compat``)
* ``replay`` — recorded responses, for tests (``replay``)

``make_backend(LLMConfig.from_env())`` builds the configured one, wrapped in the sqlite response
cache (``cache``). Modules that need llama-cpp-python or the ``openai`` SDK are imported lazily.
"""

from voxposer.lmp.backends.base import ChatMessage, LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.backends.cache import CachedBackend, ResponseCache
from voxposer.lmp.backends.config import ENV_VARS, LLMConfig, resolve_api_key
from voxposer.lmp.backends.factory import DecodingOverrides, make_backend

__all__ = [
    "ENV_VARS",
    "CachedBackend",
    "ChatMessage",
    "DecodingOverrides",
    "LLMBackend",
    "LLMConfig",
    "LLMRequest",
    "LLMResponse",
    "ResponseCache",
    "make_backend",
    "resolve_api_key",
]
