"""LLMConfig: validation naming field and value, environment parsing in one place."""

from __future__ import annotations

from pathlib import Path

import pytest

from voxposer.errors import ConfigError
from voxposer.lmp.backends import LLMConfig, resolve_api_key
from voxposer.lmp.backends.config import default_cache_dir, default_model_dir


def test_defaults_are_the_local_default_model() -> None:
    config = LLMConfig.from_env({})
    assert config.backend == "default" and config.cache and config.prefix_cache
    assert config.n_ctx >= 4096


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"backend": "gpt"}, "backend='gpt'"),
        ({"backend": "llama_cpp"}, "model"),
        ({"backend": "openai"}, "model"),
        ({"backend": "replay"}, "recordings_path"),
        ({"temperature": 3.0}, "temperature=3.0"),
        ({"max_tokens": 0}, "max_tokens=0"),
        ({"timeout": 0.0}, "timeout=0.0"),
        ({"max_retries": -1}, "max_retries=-1"),
        ({"n_ctx": 100}, "n_ctx=100"),
        ({"n_threads": 0}, "n_threads=0"),
        ({"context_cache_mib": -1}, "context_cache_mib=-1"),
    ],
)
def test_invalid_values_name_field_and_value(kwargs: dict, field: str) -> None:
    with pytest.raises(ConfigError, match=field.replace("(", r"\(")):
        LLMConfig(**kwargs)


def test_unknown_backend_lists_the_choices() -> None:
    with pytest.raises(ConfigError, match="default, llama_cpp, openai, replay"):
        LLMConfig(backend="gpt")  # type: ignore[arg-type]


def test_from_env_parses_every_type(tmp_path: Path) -> None:
    env = {
        "VOXPOSER_LLM_BACKEND": "openai",
        "VOXPOSER_LLM_MODEL": "gpt-4o-mini",
        "VOXPOSER_LLM_BASE_URL": "http://127.0.0.1:8000/v1",
        "VOXPOSER_LLM_API_KEY_ENV": "MY_KEY",
        "VOXPOSER_LLM_TEMPERATURE": "0.3",
        "VOXPOSER_LLM_MAX_TOKENS": "256",
        "VOXPOSER_LLM_TIMEOUT": "12.5",
        "VOXPOSER_LLM_MAX_RETRIES": "1",
        "VOXPOSER_LLM_N_CTX": "8192",
        "VOXPOSER_LLM_N_THREADS": "2",
        "VOXPOSER_LLM_CACHE": "off",
        "VOXPOSER_LLM_PREFIX_CACHE": "0",
        "VOXPOSER_LLM_CONTEXT_CACHE_MIB": "256",
        "VOXPOSER_LLM_CACHE_DIR": str(tmp_path / "c"),
        "VOXPOSER_MODEL_DIR": str(tmp_path / "m"),
    }
    c = LLMConfig.from_env(env)
    assert (c.backend, c.model, c.base_url, c.api_key_env) == (
        "openai", "gpt-4o-mini", "http://127.0.0.1:8000/v1", "MY_KEY",
    )  # fmt: skip
    assert (c.temperature, c.max_tokens, c.timeout, c.max_retries) == (0.3, 256, 12.5, 1)
    assert (c.n_ctx, c.n_threads, c.cache, c.prefix_cache) == (8192, 2, False, False)
    assert c.context_cache_mib == 256
    assert c.cache_dir == tmp_path / "c" and c.model_dir == tmp_path / "m"
    assert resolve_api_key(c, {"MY_KEY": "sk-1"}) == "sk-1"
    assert resolve_api_key(c, {}) is None


def test_backend_is_inferred_from_url_or_gguf_path() -> None:
    assert (
        LLMConfig.from_env(
            {"VOXPOSER_LLM_BASE_URL": "http://h/v1", "VOXPOSER_LLM_MODEL": "m"}
        ).backend
        == "openai"
    )
    assert LLMConfig.from_env({"VOXPOSER_LLM_MODEL": "/m/x.GGUF"}).backend == "llama_cpp"


def test_overrides_beat_the_environment() -> None:
    c = LLMConfig.from_env({"VOXPOSER_LLM_N_CTX": "8192"}, n_ctx=4096, model=None)
    assert c.n_ctx == 4096


@pytest.mark.parametrize(
    ("var", "value"), [("VOXPOSER_LLM_N_CTX", "big"), ("VOXPOSER_LLM_CACHE", "maybe")]
)
def test_bad_environment_values_name_the_variable(var: str, value: str) -> None:
    with pytest.raises(ConfigError, match=var):
        LLMConfig.from_env({var: value})


def test_directories_follow_their_variables(tmp_path: Path) -> None:
    assert default_model_dir({"VOXPOSER_MODEL_DIR": str(tmp_path)}) == tmp_path
    assert default_cache_dir({"VOXPOSER_CACHE_DIR": str(tmp_path)}) == tmp_path
    assert default_model_dir({"XDG_CACHE_HOME": str(tmp_path)}) == tmp_path / "voxposer" / "models"
