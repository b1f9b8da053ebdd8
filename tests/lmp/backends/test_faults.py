"""Fault injection: the OpenAI-compatible backend against a fake endpoint that misbehaves.

Every case must end, within a generous wall-clock guard (:func:`within`) that the backend's own
timeouts, retry limits and body limits keep it under, either in a successful (retried) answer
or in an :class:`EndpointError` that names the status or what happened.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.lmp.backends.bounded import within
from tests.lmp.backends.fake_openai_server import FakeOpenAIServer, Reply
from voxposer.errors import ConfigError, EndpointError, LLMError
from voxposer.lmp.backends import ChatMessage, LLMConfig, LLMRequest, make_backend
from voxposer.lmp.backends.openai_compat import OpenAICompatBackend
from voxposer.lmp.backends.retry import RetryPolicy

FAST = RetryPolicy(max_retries=2, initial_delay=0.01, max_delay=0.2)
REQUEST = LLMRequest(messages=(ChatMessage("user", "write code"),), max_tokens=64)
GUARD_S = 60.0  # far above any case's bound (a few seconds): a hang, not a slow machine
TIMEOUT_S = 1.0  # the client's per-request timeout in these tests [s]
HANG_S = 30.0  # how late a "hang" reply answers [s] (woken early when the server stops)


@pytest.fixture
def server() -> Iterator[FakeOpenAIServer]:
    with FakeOpenAIServer() as fake:
        yield fake


def backend(server: FakeOpenAIServer, retry: RetryPolicy = FAST,
            **kwargs: object) -> OpenAICompatBackend:
    return OpenAICompatBackend("fake-model", base_url=server.url, timeout=TIMEOUT_S,
                               retry=retry, **kwargs)  # type: ignore[arg-type]


def fails(server: FakeOpenAIServer, *script: Reply, **kwargs: object) -> EndpointError:
    """The EndpointError the backend ends in when ``server`` plays ``script``."""
    server.script(*script)
    llm = backend(server, **kwargs)  # type: ignore[arg-type]
    with pytest.raises(EndpointError) as info:
        within(GUARD_S, lambda: llm.complete(REQUEST))
    llm.close()
    err = info.value
    assert isinstance(err, LLMError) and err.url == server.url and err.model == "fake-model"
    assert server.url in str(err) and "fake-model" in str(err)
    return err


def succeeds(server: FakeOpenAIServer, *script: Reply, **kwargs: object) -> str:
    """The text the backend answers when ``server`` plays ``script``."""
    server.script(*script)
    llm = backend(server, **kwargs)  # type: ignore[arg-type]
    response = within(GUARD_S, lambda: llm.complete(REQUEST))
    llm.close()
    assert response.extra["attempts"] == len(server.received)
    return response.text


def test_a_normal_answer_carries_the_code_and_the_generation_limit(
        server: FakeOpenAIServer) -> None:
    assert succeeds(server, Reply.ok("ret_val = 42")) == "ret_val = 42"
    assert server.received[0].body["max_tokens"] == REQUEST.max_tokens


def test_a_hanging_endpoint_times_out_and_the_retries_are_bounded(
        server: FakeOpenAIServer) -> None:
    err = fails(server, Reply.hang(HANG_S))
    assert err.status is None and err.attempts == FAST.max_retries + 1
    assert len(server.received) == FAST.max_retries + 1
    assert f"no answer within {TIMEOUT_S:g} s" in str(err)


def test_a_total_budget_stops_the_retries_early(server: FakeOpenAIServer) -> None:
    budget = RetryPolicy(max_retries=50, initial_delay=0.01, max_delay=0.01, max_elapsed=2.5)
    err = fails(server, Reply.hang(HANG_S), retry=budget)
    assert err.status is None and err.attempts < 50
    assert "2.5 s budget" in str(err)


def test_429_then_200_succeeds_after_the_retry_after_wait(server: FakeOpenAIServer) -> None:
    patient = RetryPolicy(max_retries=2, initial_delay=0.01, max_delay=5.0)
    assert succeeds(server, Reply.error(429, retry_after="1"), Reply.ok("x = 1"),
                    retry=patient) == "x = 1"
    first, second = server.received
    assert second.at - first.at >= 0.9  # the server's hint was honoured (a lower bound only)


def test_a_huge_retry_after_is_capped_by_the_policy(server: FakeOpenAIServer) -> None:
    assert succeeds(server, Reply.error(429, retry_after="3600"), Reply.ok("x = 2")) == "x = 2"
    first, second = server.received
    assert second.at - first.at >= FAST.max_delay  # waited the cap, not an hour (the guard)


def test_endless_429_ends_naming_the_status_and_the_hint(server: FakeOpenAIServer) -> None:
    err = fails(server, Reply.error(429, retry_after="0"))
    assert err.status == 429 and err.attempts == FAST.max_retries + 1
    assert "HTTP 429" in str(err) and "Retry-After: 0 s" in str(err)


@pytest.mark.parametrize("status", [500, 503])
def test_server_errors_are_retried_then_named(server: FakeOpenAIServer, status: int) -> None:
    err = fails(server, Reply.error(status))
    assert err.status == status and err.attempts == FAST.max_retries + 1
    assert f"HTTP {status}" in str(err)


def test_a_503_then_a_200_succeeds(server: FakeOpenAIServer) -> None:
    assert succeeds(server, Reply.error(503), Reply.ok("y = 3")) == "y = 3"


def test_a_client_error_after_a_retry_counts_both_attempts(server: FakeOpenAIServer) -> None:
    err = fails(server, Reply.error(503), Reply.error(400))
    assert err.status == 400 and err.attempts == 2 and "HTTP 400" in str(err)


def test_a_connection_cut_mid_body_is_retried_then_named(server: FakeOpenAIServer) -> None:
    err = fails(server, Reply("cut"))
    assert err.status is None and err.attempts == FAST.max_retries + 1
    assert "connection lost" in str(err)


def test_a_cut_then_a_full_answer_succeeds(server: FakeOpenAIServer) -> None:
    assert succeeds(server, Reply("cut"), Reply.ok("z = 4")) == "z = 4"


def test_truncated_json_is_an_endpoint_error_not_a_decode_error(
        server: FakeOpenAIServer) -> None:
    err = fails(server, Reply("truncated_json"))
    assert err.status == 200 and err.attempts == FAST.max_retries + 1
    assert "truncated or invalid JSON" in str(err)


def test_truncated_json_then_a_full_answer_succeeds(server: FakeOpenAIServer) -> None:
    assert succeeds(server, Reply("truncated_json"), Reply.ok("w = 5")) == "w = 5"


def test_a_200_that_is_not_json_names_its_content_type(server: FakeOpenAIServer) -> None:
    err = fails(server, Reply("not_json"))
    assert err.status == 200 and "text/html" in str(err) and "Bad Gateway" in str(err)


def test_json_that_is_no_chat_completion_fails_at_once(server: FakeOpenAIServer) -> None:
    err = fails(server, Reply("wrong_shape"))
    assert err.status == 200 and err.attempts == 1 and len(server.received) == 1
    assert "no choices" in str(err)


def test_non_code_text_is_returned_as_it_is(server: FakeOpenAIServer) -> None:
    """The backend does not judge the text: the LMP runtime does (test_faults_runtime)."""
    prose = "I'm sorry, I can't write code for robots."
    assert succeeds(server, Reply.ok(prose)) == prose


def test_an_answer_past_max_tokens_is_refused_naming_the_limit(
        server: FakeOpenAIServer) -> None:
    err = fails(server, Reply.ok("x = 1\n" * 5_000))
    assert err.status == 200 and err.attempts == 1
    assert f"max_tokens={REQUEST.max_tokens}" in str(err) and "30000 characters" in str(err)


def test_an_endless_body_stops_at_the_size_cap_without_retrying(
        server: FakeOpenAIServer) -> None:
    err = fails(server, Reply.endless(), max_body_bytes=1_000_000)
    assert err.status == 200 and err.attempts == 1 and len(server.received) == 1
    assert "HTTP 200 response exceeded 1000000 bytes" in str(err)


def test_an_endless_trickle_stops_at_the_timeout(server: FakeOpenAIServer) -> None:
    """Bytes keep coming, so no single read times out: the body's own deadline must."""
    err = fails(server, Reply.endless(delay=0.02))
    assert err.status is None and err.attempts == FAST.max_retries + 1
    assert f"no complete answer within {TIMEOUT_S:g} s" in str(err)
    assert "still arriving" in str(err)


def test_the_config_total_timeout_becomes_the_retry_budget(server: FakeOpenAIServer) -> None:
    config = LLMConfig(backend="openai", model="fake-model", base_url=server.url,
                       total_timeout=7.0, cache=False)
    llm = make_backend(config)
    assert isinstance(llm, OpenAICompatBackend) and llm.retry.max_elapsed == 7.0
    llm.close()
    assert LLMConfig.from_env({"VOXPOSER_LLM_TOTAL_TIMEOUT": "30"}).total_timeout == 30.0
    with pytest.raises(ConfigError, match="total_timeout=0"):
        LLMConfig(total_timeout=0.0)
