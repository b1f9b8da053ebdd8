"""Any OpenAI-compatible chat endpoint: OpenAI, vLLM, Ollama, llama.cpp's server, LM Studio.

Uses the official ``openai`` SDK with its own retries switched off: connection failures (refused,
or cut mid-answer), timeouts, 408, 429 and 5xx, and bodies garbled in transit are retried here a
bounded number of times with exponential backoff (a server's Retry-After honoured up to the
policy's cap), within an optional total time budget, then raised as one
:class:`voxposer.errors.EndpointError` that names the URL, the model, the last status and what
went wrong. Other statuses (400, 401, 404, …), bodies that are not chat completions, and answers
longer than ``max_tokens`` allows fail at once. Every request has a timeout that also bounds how
long its body may keep arriving, and a size cap (:mod:`voxposer.lmp.backends.body_limits`), so
neither a stalled nor an endless answer hangs. The API key is passed in (read from the
environment by the config), never read here.
"""

from __future__ import annotations

import email.utils
import itertools
import logging
import math
import time
from collections.abc import Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import cast

import httpx2
import openai
from openai.types.chat import ChatCompletionMessageParam

from voxposer.errors import ConfigError, EndpointError
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.backends.body_limits import (
    DEFAULT_MAX_BODY_BYTES,
    BodyDeadlineError,
    BodyTooLargeError,
    body_limits_hook,
)
from voxposer.lmp.backends.chat_body import ChatAnswer, ChatBodyError, parse_chat_body
from voxposer.lmp.backends.retry import RetryableError, RetryPolicy, call_with_retries

log = logging.getLogger(__name__)

OPENAI_URL = "https://api.openai.com/v1"
#: sent when no key is configured; local servers (vLLM, Ollama, llama.cpp) ignore it
NO_KEY = "no-key"
MAX_CONCURRENT = 4  # requests of one complete_many call in flight at once
#: statuses worth asking again: request timeout, rate limit, and server errors (5xx)
RETRYABLE_STATUSES = frozenset({408, 429})
#: shortest time an attempt is given when the budget is nearly spent [s]
MIN_ATTEMPT_TIMEOUT = 0.05


class OpenAICompatBackend(LLMBackend):
    """Chat completions from an OpenAI-compatible HTTP endpoint.

    Args:
        model: model name as the endpoint knows it (e.g. "gpt-4o-mini", "qwen2.5-coder:1.5b").
        base_url: the API root, e.g. "http://127.0.0.1:8080/v1"; None = OpenAI's.
        api_key: the key, or None for endpoints that need none.
        timeout: limit of one HTTP request [s]: each connect, read and write, and also the
            whole response body from its headers on.
        retry: how often, how patiently and for how long in total to retry.
        max_body_bytes: most bytes one response body may hold [bytes].
    """

    name = "openai"

    def __init__(
        self,
        model: str,
        base_url: str | None = None,
        api_key: str | None = None,
        timeout: float = 120.0,
        retry: RetryPolicy | None = None,
        max_body_bytes: int = DEFAULT_MAX_BODY_BYTES,
    ) -> None:
        if not model:
            raise ConfigError("model='' must name the endpoint's model")
        if not timeout > 0:
            raise ConfigError(f"timeout={timeout} s must be > 0")
        self._model = model
        self.base_url = (base_url or OPENAI_URL).rstrip("/")
        self.timeout = float(timeout)
        self.retry = retry or RetryPolicy()
        http = openai.DefaultHttpxClient(
            timeout=self.timeout,
            event_hooks={"response": [body_limits_hook(max_body_bytes, self.timeout)]},
        )
        self._client = openai.OpenAI(
            api_key=api_key or NO_KEY,
            base_url=self.base_url,
            timeout=self.timeout,
            max_retries=0,
            http_client=http,
        )

    @property
    def model(self) -> str:
        return self._model

    def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        """The requests sent concurrently (at most ``MAX_CONCURRENT`` at a time), answers in
        their order; the first failure is raised."""
        if len(requests) < 2:
            return super().complete_many(requests)
        with ThreadPoolExecutor(min(len(requests), MAX_CONCURRENT)) as pool:
            return list(pool.map(self.complete, requests))

    def complete(self, request: LLMRequest) -> LLMResponse:
        start = time.monotonic()
        budget = self.retry.max_elapsed
        deadline = None if budget is None else start + budget
        tries = itertools.count(1)
        try:
            answer, attempts = call_with_retries(
                lambda: self._attempt(request, deadline, next(tries)), self.retry)
        except RetryableError as exc:
            stop = (f"; stopped retrying: the next try would pass the {budget:g} s budget"
                    if exc.out_of_time else "")
            raise self._error(
                f"failed after {exc.attempts} attempt(s) in {exc.elapsed:.1f} s: {exc}{stop}",
                status=exc.status, attempts=exc.attempts) from exc
        return LLMResponse(
            text=answer.text,
            model=self._model,
            prompt_tokens=answer.prompt_tokens,
            completion_tokens=answer.completion_tokens,
            seconds=time.monotonic() - start,
            extra={"finish_reason": answer.finish_reason, "attempts": attempts},
        )

    def _attempt(self, request: LLMRequest, deadline: float | None, n: int) -> ChatAnswer:
        """Attempt number ``n``; failures worth repeating become :class:`RetryableError`."""
        timeout = self.timeout
        if deadline is not None:
            timeout = max(MIN_ATTEMPT_TIMEOUT, min(timeout, deadline - time.monotonic()))
        try:
            raw = self._client.chat.completions.with_raw_response.create(
                model=self._model,
                messages=cast(
                    "list[ChatCompletionMessageParam]",
                    [{"role": m.role, "content": m.content} for m in request.messages],
                ),
                temperature=request.temperature,
                max_tokens=request.max_tokens,
                stop=list(request.stop) if request.stop else None,
                timeout=timeout,
            )
        except openai.APITimeoutError as exc:
            late = isinstance(exc.__cause__, BodyDeadlineError)
            raise RetryableError(f"no {'complete ' if late else ''}answer within {timeout:.3g} s"
                                 + (f" ({exc.__cause__})" if late else "")) from exc
        except openai.APIConnectionError as exc:
            refused = isinstance(exc.__cause__, httpx2.ConnectError)
            raise RetryableError(
                f"{'cannot connect' if refused else 'connection lost'} ({_cause(exc)})") from exc
        except openai.APIStatusError as exc:
            raise self._status_error(exc, n) from exc
        except BodyTooLargeError as exc:
            raise self._error(f"sent an endless or runaway answer: {exc}", status=exc.status,
                              attempts=n) from exc
        except openai.OpenAIError as exc:
            raise self._error(f"failed in the openai SDK: {type(exc).__name__}: {_short(str(exc))}",
                              status=None, attempts=n) from exc
        try:
            return parse_chat_body(raw.http_response.content,
                                   raw.headers.get("content-type", ""), request.max_tokens)
        except ChatBodyError as exc:
            if exc.retryable:
                raise RetryableError(f"HTTP 200 with {exc}", 200) from exc
            raise self._error(f"answered HTTP 200 with {exc}", status=200, attempts=n) from exc

    def _status_error(self, exc: openai.APIStatusError, n: int) -> Exception:
        """The error to raise for an error status: retryable, or an EndpointError at once."""
        status = exc.status_code
        detail = _short(str(exc.message))
        if status in RETRYABLE_STATUSES or status >= 500:
            wait = retry_after(exc.response.headers) if exc.response is not None else None
            hint = "" if wait is None else f" (Retry-After: {wait:g} s)"
            return RetryableError(f"HTTP {status}: {detail}{hint}", status, wait)
        hint = ""
        if status in (401, 403):
            hint = " (check the API key: LLMConfig.api_key_env names its variable)"
        elif status == 404:
            hint = " (check the base URL and that the endpoint serves this model)"
        return self._error(f"answered HTTP {status}: {detail}{hint}", status=status, attempts=n)

    def _error(self, what: str, status: int | None, attempts: int) -> EndpointError:
        return EndpointError(
            f"LLM endpoint {self.base_url} (model {self._model!r}) {what}",
            url=self.base_url, model=self._model, status=status, attempts=attempts)

    def close(self) -> None:
        self._client.close()


def retry_after(headers: Mapping[str, str]) -> float | None:
    """A server's wait hint [s] from ``retry-after-ms``, or ``retry-after`` as seconds or an
    HTTP date; None when absent or unreadable. Never negative."""
    for name, scale in (("retry-after-ms", 1e-3), ("retry-after", 1.0)):
        value = headers.get(name)
        if value is None:
            continue
        try:
            seconds = float(value) * scale
        except ValueError:
            continue
        return None if math.isnan(seconds) else max(0.0, seconds)
    value = headers.get("retry-after")
    parsed = email.utils.parsedate_tz(value) if value else None
    if parsed is None:
        return None
    return max(0.0, float(email.utils.mktime_tz(parsed)) - time.time())


def _cause(exc: BaseException) -> str:
    inner = exc.__cause__ or exc.__context__
    return _short(f"{type(inner).__name__}: {inner}" if inner else str(exc))


def _short(text: str, limit: int = 300) -> str:
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 1] + "…"
