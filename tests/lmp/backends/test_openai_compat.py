"""The OpenAI-compatible backend: bounded retries and clear errors against a misbehaving local
server, and real completions from llama-cpp-python's OpenAI-compatible server."""

from __future__ import annotations

import time

import pytest

from tests.lmp.backends.conftest import StubServer, chat_body, free_port
from voxposer.errors import EndpointError, LLMError
from voxposer.lmp.backends import ChatMessage, LLMConfig, LLMRequest, make_backend
from voxposer.lmp.backends.openai_compat import OpenAICompatBackend
from voxposer.lmp.backends.retry import RetryPolicy

FAST = RetryPolicy(max_retries=2, initial_delay=0.01, max_delay=0.05)
REQUEST = LLMRequest(messages=(ChatMessage("user", "say hi"),), max_tokens=8)


def backend(url: str, timeout: float = 5.0, retry: RetryPolicy = FAST) -> OpenAICompatBackend:
    return OpenAICompatBackend("stub-model", base_url=url, timeout=timeout, retry=retry)


def test_success_returns_text_usage_and_sends_the_request(stub_server: StubServer) -> None:
    stub_server.script = [(200, chat_body("y = 2"), {}, 0.0)]
    request = LLMRequest(
        messages=(ChatMessage("system", "be brief"), ChatMessage("user", "q")),
        temperature=0.0,
        max_tokens=7,
        stop=("#",),
    )
    response = backend(stub_server.url).complete(request)
    assert response.text == "y = 2"
    assert (response.prompt_tokens, response.completion_tokens) == (5, 3)
    assert not response.cached
    sent = stub_server.requests[0]
    assert sent["model"] == "stub-model"
    assert sent["messages"] == [
        {"role": "system", "content": "be brief"},
        {"role": "user", "content": "q"},
    ]
    assert (sent["max_tokens"], sent["temperature"], sent["stop"]) == (7, 0.0, ["#"])


def test_requests_together_are_all_sent_and_answered(stub_server: StubServer) -> None:
    stub_server.script = [(200, chat_body("y = 2"), {}, 0.0)]
    queries = ["a", "b", "c"]
    answers = backend(stub_server.url).complete_many(
        [LLMRequest(messages=(ChatMessage("user", q),), max_tokens=8) for q in queries])
    assert [a.text for a in answers] == ["y = 2"] * 3
    assert sorted(r["messages"][0]["content"] for r in stub_server.requests) == queries
    stub_server.script = [(400, {"error": {"message": "bad"}}, {}, 0.0)]
    with pytest.raises(EndpointError, match="400"):
        backend(stub_server.url).complete_many([REQUEST, REQUEST])


@pytest.mark.parametrize("status", [500, 502, 503, 429])
def test_retryable_status_is_retried_then_raises_naming_url_model_status(
    stub_server: StubServer, status: int
) -> None:
    stub_server.script = [(status, {"error": {"message": "busy"}}, {}, 0.0)]
    with pytest.raises(EndpointError) as info:
        backend(stub_server.url).complete(REQUEST)
    err = info.value
    assert len(stub_server.requests) == FAST.max_retries + 1
    assert (err.status, err.attempts, err.url, err.model) == (
        status,
        3,
        stub_server.url,
        "stub-model",
    )
    assert stub_server.url in str(err) and "stub-model" in str(err) and str(status) in str(err)
    assert isinstance(err, LLMError)


def test_recovers_when_a_retry_succeeds(stub_server: StubServer) -> None:
    stub_server.script = [
        (503, {"error": {"message": "loading"}}, {}, 0.0),
        (429, {"error": {"message": "slow down"}}, {"retry-after": "0"}, 0.0),
        (200, chat_body("ok"), {}, 0.0),
    ]
    response = backend(stub_server.url).complete(REQUEST)
    assert response.text == "ok"
    assert response.extra["attempts"] == 3


@pytest.mark.parametrize("status", [400, 401, 404])
def test_client_errors_fail_at_once(stub_server: StubServer, status: int) -> None:
    stub_server.script = [(status, {"error": {"message": "nope"}}, {}, 0.0)]
    with pytest.raises(EndpointError) as info:
        backend(stub_server.url).complete(REQUEST)
    assert len(stub_server.requests) == 1
    assert info.value.status == status and info.value.attempts == 1


def test_hanging_server_times_out_and_retries_are_bounded(stub_server: StubServer) -> None:
    stub_server.script = [(200, chat_body(), {}, 30.0)]  # answers far too late
    start = time.monotonic()
    with pytest.raises(EndpointError) as info:
        backend(stub_server.url, timeout=0.5, retry=RetryPolicy(1, 0.01, 0.01)).complete(REQUEST)
    elapsed = time.monotonic() - start
    assert info.value.status is None and info.value.attempts == 2
    assert "0.5 s" in str(info.value)
    assert elapsed < 10.0


def test_endpoint_down_raises_connection_error_after_retries() -> None:
    url = f"http://127.0.0.1:{free_port()}/v1"  # nothing listens there
    with pytest.raises(EndpointError) as info:
        backend(url).complete(REQUEST)
    assert info.value.status is None and info.value.attempts == 3
    assert "cannot connect" in str(info.value) and url in str(info.value)


def test_api_key_is_sent_from_the_config_variable(
    stub_server: StubServer, clean_env: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    stub_server.script = [(200, chat_body(), {}, 0.0)]
    monkeypatch.setenv("MY_KEY", "sk-test-123")
    config = LLMConfig(
        backend="openai", model="stub-model", base_url=stub_server.url, api_key_env="MY_KEY",
        cache=False,
    )  # fmt: skip
    llm = make_backend(config)
    assert isinstance(llm, OpenAICompatBackend)
    llm.complete(REQUEST)
    assert stub_server.headers[0]["authorization"] == "Bearer sk-test-123"


def test_missing_key_still_works_for_local_servers(
    stub_server: StubServer, clean_env: None
) -> None:
    stub_server.script = [(200, chat_body("fine"), {}, 0.0)]
    config = LLMConfig(backend="openai", model="m", base_url=stub_server.url, cache=False)
    assert make_backend(config).complete(REQUEST).text == "fine"


def test_real_llama_cpp_server(llama_server: str) -> None:
    llm = OpenAICompatBackend("default", base_url=llama_server, timeout=300.0)
    response = llm.complete(
        LLMRequest(
            messages=(ChatMessage("user", "Write one line of Python that sets x to 3."),),
            max_tokens=24,
        )
    )
    llm.close()
    assert "x" in response.text and "3" in response.text
    assert response.prompt_tokens > 0 and response.completion_tokens > 0


def test_real_server_unknown_route_is_a_clear_error(llama_server: str) -> None:
    llm = OpenAICompatBackend("default", base_url=llama_server + "/nowhere", timeout=30.0)
    with pytest.raises(EndpointError) as info:
        llm.complete(REQUEST)
    assert info.value.status == 404 and "/nowhere" in str(info.value)
