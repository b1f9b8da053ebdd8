"""Any OpenAI-compatible chat endpoint: OpenAI, vLLM, Ollama, llama.cpp's server, LM Studio.

Uses the official ``openai`` SDK with its own retries switched off: connection failures,
timeouts, 429 and 5xx are retried here a bounded number of times with exponential backoff, then
raised as one :class:`voxposer.errors.EndpointError` that names the URL, the model and the last
status. Other statuses (400, 401, 404, …) fail at once. Every request has a timeout, so nothing
hangs. The API key is passed in (read from the environment by the config), never read here.
"""

from __future__ import annotations

import logging
import time
from typing import cast

import openai
from openai.types.chat import ChatCompletionMessageParam

from voxposer.errors import ConfigError, EndpointError
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.backends.retry import RetryableError, RetryPolicy, call_with_retries

log = logging.getLogger(__name__)

OPENAI_URL = "https://api.openai.com/v1"
#: sent when no key is configured; local servers (vLLM, Ollama, llama.cpp) ignore it
NO_KEY = "no-key"


class OpenAICompatBackend(LLMBackend):
    """Chat completions from an OpenAI-compatible HTTP endpoint.

    Args:
        model: model name as the endpoint knows it (e.g. "gpt-4o-mini", "qwen2.5-coder:1.5b").
        base_url: the API root, e.g. "http://127.0.0.1:8080/v1"; None = OpenAI's.
        api_key: the key, or None for endpoints that need none.
        timeout: limit of one HTTP request [s] (connect, read and write).
        retry: how often to retry connection errors, timeouts, 429 and 5xx.
    """

    name = "openai"

    def __init__(
        self,
        model: str,
        base_url: str | None = None,
        api_key: str | None = None,
        timeout: float = 120.0,
        retry: RetryPolicy | None = None,
    ) -> None:
        if not model:
            raise ConfigError("model='' must name the endpoint's model")
        if not timeout > 0:
            raise ConfigError(f"timeout={timeout} s must be > 0")
        self._model = model
        self.base_url = (base_url or OPENAI_URL).rstrip("/")
        self.timeout = float(timeout)
        self.retry = retry or RetryPolicy()
        self._client = openai.OpenAI(
            api_key=api_key or NO_KEY,
            base_url=self.base_url,
            timeout=self.timeout,
            max_retries=0,
        )

    @property
    def model(self) -> str:
        return self._model

    def complete(self, request: LLMRequest) -> LLMResponse:
        start = time.perf_counter()
        try:
            completion, attempts = call_with_retries(lambda: self._attempt(request), self.retry)
        except RetryableError as exc:
            raise EndpointError(
                f"LLM endpoint {self.base_url} (model {self._model!r}) failed after "
                f"{exc.attempts} attempt(s): {exc}",
                url=self.base_url,
                model=self._model,
                status=exc.status,
                attempts=exc.attempts,
            ) from exc
        seconds = time.perf_counter() - start
        if not completion.choices:
            raise EndpointError(
                f"LLM endpoint {self.base_url} (model {self._model!r}) returned no choices",
                url=self.base_url,
                model=self._model,
                status=200,
                attempts=attempts,
            )
        choice = completion.choices[0]
        usage = completion.usage
        return LLMResponse(
            text=choice.message.content or "",
            model=self._model,
            prompt_tokens=usage.prompt_tokens if usage else 0,
            completion_tokens=usage.completion_tokens if usage else 0,
            seconds=seconds,
            extra={"finish_reason": choice.finish_reason, "attempts": attempts},
        )

    def _attempt(self, request: LLMRequest) -> openai.types.chat.ChatCompletion:
        """One HTTP request; retryable failures become :class:`RetryableError`."""
        try:
            return self._client.chat.completions.create(
                model=self._model,
                messages=cast(
                    "list[ChatCompletionMessageParam]",
                    [{"role": m.role, "content": m.content} for m in request.messages],
                ),
                temperature=request.temperature,
                max_tokens=request.max_tokens,
                stop=list(request.stop) if request.stop else None,
            )
        except openai.APITimeoutError as exc:
            raise RetryableError(f"no answer within {self.timeout:g} s") from exc
        except openai.APIConnectionError as exc:
            raise RetryableError(f"cannot connect ({_cause(exc)})") from exc
        except openai.APIStatusError as exc:
            status = exc.status_code
            detail = _short(str(exc.message))
            if status == 429 or status >= 500:
                raise RetryableError(f"HTTP {status}: {detail}", status, _retry_after(exc)) from exc
            hint = ""
            if status in (401, 403):
                hint = " (check the API key: LLMConfig.api_key_env names its variable)"
            elif status == 404:
                hint = " (check the base URL and that the endpoint serves this model)"
            raise EndpointError(
                f"LLM endpoint {self.base_url} (model {self._model!r}) answered HTTP "
                f"{status}: {detail}{hint}",
                url=self.base_url,
                model=self._model,
                status=status,
                attempts=1,
            ) from exc

    def close(self) -> None:
        self._client.close()


def _cause(exc: BaseException) -> str:
    inner = exc.__cause__ or exc.__context__
    return _short(f"{type(inner).__name__}: {inner}" if inner else str(exc))


def _short(text: str, limit: int = 300) -> str:
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _retry_after(exc: openai.APIStatusError) -> float | None:
    value = exc.response.headers.get("retry-after") if exc.response is not None else None
    try:
        return float(value) if value is not None else None
    except ValueError:
        return None
