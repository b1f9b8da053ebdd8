"""Typed configuration of the LLM backend, and the ONE place that reads environment variables.

Every setting has a ``VOXPOSER_LLM_*`` variable (see :data:`ENV_VARS`); :meth:`LLMConfig.from_env`
reads them, :func:`resolve_api_key` reads the API key variable named by the config, and
:func:`default_model_dir` / :func:`default_cache_dir` read ``VOXPOSER_MODEL_DIR`` /
``VOXPOSER_CACHE_DIR``. Library code below this module never touches ``os.environ``.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping, MutableMapping
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, get_args

from voxposer.errors import ConfigError

BackendKind = Literal["default", "llama_cpp", "openai", "replay"]
BACKEND_KINDS: tuple[str, ...] = get_args(BackendKind)

#: environment variable → LLMConfig field
ENV_VARS: dict[str, str] = {
    "VOXPOSER_LLM_BACKEND": "backend",
    "VOXPOSER_LLM_MODEL": "model",
    "VOXPOSER_LLM_BASE_URL": "base_url",
    "VOXPOSER_LLM_API_KEY_ENV": "api_key_env",
    "VOXPOSER_LLM_TEMPERATURE": "temperature",
    "VOXPOSER_LLM_MAX_TOKENS": "max_tokens",
    "VOXPOSER_LLM_TIMEOUT": "timeout",
    "VOXPOSER_LLM_MAX_RETRIES": "max_retries",
    "VOXPOSER_LLM_TOTAL_TIMEOUT": "total_timeout",
    "VOXPOSER_LLM_N_CTX": "n_ctx",
    "VOXPOSER_LLM_N_THREADS": "n_threads",
    "VOXPOSER_LLM_CACHE": "cache",
    "VOXPOSER_LLM_PREFIX_CACHE": "prefix_cache",
    "VOXPOSER_LLM_CONTEXT_CACHE_MIB": "context_cache_mib",
    "VOXPOSER_LLM_CACHE_DIR": "cache_dir",
    "VOXPOSER_LLM_PREFIX_CACHE_DIR": "prefix_cache_dir",
    "VOXPOSER_LLM_RECORDINGS": "recordings_path",
}
MODEL_DIR_ENV = "VOXPOSER_MODEL_DIR"
CACHE_DIR_ENV = "VOXPOSER_CACHE_DIR"

_TRUE = {"1", "true", "yes", "on"}
_FALSE = {"0", "false", "no", "off", ""}


def _xdg_cache(environ: Mapping[str, str]) -> Path:
    base = environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base).expanduser() / "voxposer"


def default_cache_dir(environ: Mapping[str, str] | None = None) -> Path:
    """Root of voxposer's caches: ``$VOXPOSER_CACHE_DIR`` or ``~/.cache/voxposer``."""
    env = os.environ if environ is None else environ
    override = env.get(CACHE_DIR_ENV)
    return Path(override).expanduser() if override else _xdg_cache(env)


def default_model_dir(environ: Mapping[str, str] | None = None) -> Path:
    """Where the default model is assembled: ``$VOXPOSER_MODEL_DIR`` or ``<cache>/models``."""
    env = os.environ if environ is None else environ
    override = env.get(MODEL_DIR_ENV)
    return Path(override).expanduser() if override else default_cache_dir(env) / "models"


OPENMP_ENV = {"OMP_WAIT_POLICY": "PASSIVE"}


def configure_openmp(environ: MutableMapping[str, str] | None = None) -> None:
    """Make OpenMP threads sleep rather than spin at barriers (unless the user chose otherwise).

    Must run before llama-cpp-python is imported (libgomp reads it once, when loaded). Measured
    on 2 shared cores: spinning threads collapse decoding to 0.5-1 token/s as soon as another
    process competes for the CPU; passive waiting keeps ~17 token/s (the single-thread speed)
    and costs nothing in prompt evaluation.
    """
    env = os.environ if environ is None else environ
    for name, value in OPENMP_ENV.items():
        env.setdefault(name, value)


def openmp_configured(environ: Mapping[str, str] | None = None) -> bool:
    """Whether the OpenMP wait policy is set (by :func:`configure_openmp` or the user)."""
    env = os.environ if environ is None else environ
    return all(name in env for name in OPENMP_ENV)


def available_cores() -> int:
    """CPU cores this process may run on (its affinity mask), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


@dataclass(frozen=True)
class LLMConfig:
    """Which LLM answers the language model programs, and how.

    Attributes:
        backend: "default" (the bundled Qwen2.5-Coder-1.5B GGUF, in-process), "llama_cpp"
            (any GGUF file, in-process), "openai" (any OpenAI-compatible endpoint: OpenAI, vLLM,
            Ollama, llama.cpp's server, LM Studio) or "replay" (recorded responses; tests).
        model: GGUF file path for "llama_cpp"; model name for "openai"; unused otherwise.
        base_url: endpoint for "openai", e.g. "http://127.0.0.1:8080/v1"; None = OpenAI's.
        api_key_env: name of the environment variable holding the API key ("openai" only; local
            servers accept a missing key).
        temperature: overrides every request's temperature when set.
        max_tokens: overrides every request's generation limit [tokens] when set.
        timeout: one HTTP request's limit [s] ("openai").
        max_retries: retries after the first attempt on connection errors, timeouts, 429, 5xx.
        total_timeout: time budget of one completion, every attempt and wait included [s]
            ("openai"); None = bounded by ``timeout`` × (``max_retries`` + 1) plus the waits.
        n_ctx: context window of in-process models [tokens].
        n_threads: CPU threads of in-process models; None = the cores available.
        cache: keep a persistent sqlite cache of responses (keyed by backend, model, request).
        prefix_cache: persist evaluated few-shot prefixes (KV state) to disk ("llama_cpp").
        context_cache_mib: memory for the model states after each query's retrieved examples
            [MiB] ("llama_cpp"; ~60 MiB each for the default model); 0 keeps none.
        cache_dir: directory of the response cache (and of the prefix states unless
            ``prefix_cache_dir`` is set); None = ``default_cache_dir()``.
        prefix_cache_dir: directory of the prefix-state (KV) store; None = the cache directory.
            It caches evaluated prompt prefixes, not responses, so a run with a fresh response
            cache (``voxposer bench --fresh-cache``) keeps sharing it.
        model_dir: where the default model is assembled; None = ``default_model_dir()``.
        recordings_path: recordings file for "replay".
    """

    backend: BackendKind = "default"
    model: str | None = None
    base_url: str | None = None
    api_key_env: str = "OPENAI_API_KEY"
    temperature: float | None = None
    max_tokens: int | None = None
    timeout: float = 120.0
    max_retries: int = 3
    total_timeout: float | None = None
    n_ctx: int = 4096
    n_threads: int | None = None
    cache: bool = True
    prefix_cache: bool = True
    context_cache_mib: int = 768
    cache_dir: Path | None = None
    prefix_cache_dir: Path | None = None
    model_dir: Path | None = None
    recordings_path: Path | None = None

    def __post_init__(self) -> None:
        if self.backend not in BACKEND_KINDS:
            raise ConfigError(
                f"backend={self.backend!r} is unknown; choose one of: {', '.join(BACKEND_KINDS)}"
            )
        if self.backend == "llama_cpp" and not self.model:
            raise ConfigError("backend='llama_cpp' needs model=<path to a .gguf file>")
        if self.backend == "openai" and not self.model:
            raise ConfigError("backend='openai' needs model=<model name served by the endpoint>")
        if self.backend == "replay" and self.recordings_path is None:
            raise ConfigError("backend='replay' needs recordings_path=<recordings file>")
        if self.temperature is not None and not 0.0 <= self.temperature <= 2.0:
            raise ConfigError(f"temperature={self.temperature} must lie in [0, 2]")
        if self.max_tokens is not None and self.max_tokens < 1:
            raise ConfigError(f"max_tokens={self.max_tokens} must be >= 1")
        if not self.timeout > 0:
            raise ConfigError(f"timeout={self.timeout} s must be > 0")
        if self.max_retries < 0:
            raise ConfigError(f"max_retries={self.max_retries} must be >= 0")
        if self.total_timeout is not None and not self.total_timeout > 0:
            raise ConfigError(f"total_timeout={self.total_timeout} s must be > 0 (or None)")
        if self.n_ctx < 512:
            raise ConfigError(f"n_ctx={self.n_ctx} tokens must be >= 512")
        if self.n_threads is not None and self.n_threads < 1:
            raise ConfigError(f"n_threads={self.n_threads} must be >= 1 (or None = all cores)")
        if self.context_cache_mib < 0:
            raise ConfigError(f"context_cache_mib={self.context_cache_mib} must be >= 0 "
                              "(0 keeps no query context)")
        if not self.api_key_env:
            raise ConfigError("api_key_env='' must name an environment variable")

    @property
    def resolved_cache_dir(self) -> Path:
        """The cache directory to use (``cache_dir`` or the default)."""
        return self.cache_dir if self.cache_dir is not None else default_cache_dir()

    @property
    def resolved_prefix_cache_dir(self) -> Path:
        """The prefix-state store's parent directory (``prefix_cache_dir`` or the cache's)."""
        return self.prefix_cache_dir if self.prefix_cache_dir is not None else \
            self.resolved_cache_dir

    @property
    def resolved_model_dir(self) -> Path:
        """The default model's directory (``model_dir`` or the default)."""
        return self.model_dir if self.model_dir is not None else default_model_dir()

    @property
    def resolved_threads(self) -> int:
        """Threads for in-process inference."""
        return self.n_threads if self.n_threads is not None else available_cores()

    @classmethod
    def from_env(cls, environ: Mapping[str, str] | None = None, **overrides: object) -> LLMConfig:
        """Build a config from ``VOXPOSER_LLM_*`` variables; ``overrides`` (e.g. CLI flags) win.

        When ``VOXPOSER_LLM_BACKEND`` is unset the kind is inferred: a base URL means "openai",
        a model path ending in ``.gguf`` means "llama_cpp", otherwise "default".
        """
        env = os.environ if environ is None else environ
        values: dict[str, object] = {}
        for var, name in ENV_VARS.items():
            raw = env.get(var)
            if raw is not None and raw.strip() != "":
                values[name] = _parse(name, var, raw.strip())
        values.update({k: v for k, v in overrides.items() if v is not None})
        if "backend" not in values:
            if values.get("base_url"):
                values["backend"] = "openai"
            elif str(values.get("model", "")).lower().endswith(".gguf"):
                values["backend"] = "llama_cpp"
        model_dir = env.get(MODEL_DIR_ENV)
        if model_dir and "model_dir" not in values:
            values["model_dir"] = Path(model_dir).expanduser()
        if "cache_dir" not in values:
            values["cache_dir"] = default_cache_dir(env)
        return cls(**values)  # type: ignore[arg-type]


def resolve_api_key(config: LLMConfig, environ: Mapping[str, str] | None = None) -> str | None:
    """The API key from the variable ``config.api_key_env`` names (None when unset)."""
    env = os.environ if environ is None else environ
    return env.get(config.api_key_env) or None


def _parse(name: str, var: str, raw: str) -> object:
    field_types = {f.name: f.type for f in dataclasses.fields(LLMConfig)}
    kind = str(field_types[name])
    try:
        if kind in ("bool",):
            low = raw.lower()
            if low in _TRUE:
                return True
            if low in _FALSE:
                return False
            raise ValueError(raw)
        if kind.startswith("int"):
            return int(raw)
        if kind.startswith("float"):
            return float(raw)
        if kind.startswith("Path"):
            return Path(raw).expanduser()
    except ValueError:
        raise ConfigError(f"{var}={raw!r} is not a valid {kind} (field {name})") from None
    return raw
