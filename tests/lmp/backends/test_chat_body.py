"""Reading chat completion bodies strictly, body limits, Retry-After hints, and the retry
loop's budget."""

from __future__ import annotations

import email.utils
import json
import time

import pytest

from tests.lmp.backends.fake_openai_server import chat_completion
from voxposer.errors import ConfigError
from voxposer.lmp.backends.body_limits import body_limits_hook
from voxposer.lmp.backends.chat_body import MAX_CHARS_PER_TOKEN, ChatBodyError, parse_chat_body
from voxposer.lmp.backends.openai_compat import retry_after
from voxposer.lmp.backends.retry import RetryableError, RetryPolicy, call_with_retries

JSON = "application/json"


def body(data: object) -> bytes:
    return json.dumps(data).encode()


def test_a_valid_completion_gives_text_reason_and_usage() -> None:
    answer = parse_chat_body(body(chat_completion("x = 1", "length")), JSON, max_tokens=16)
    assert answer == ("x = 1", "length", 7, 3)


def test_missing_content_and_usage_read_as_empty_and_zero() -> None:
    data = {"choices": [{"message": {"role": "assistant", "content": None}}]}
    assert parse_chat_body(body(data), JSON, max_tokens=16) == ("", None, 0, 0)


@pytest.mark.parametrize(
    ("raw", "content_type", "retryable", "says"),
    [
        (b'{"choices": [{"mess', JSON, True, "truncated or invalid JSON"),
        (b"<html>oops</html>", "text/html", True, "text/html content, not JSON"),
        (b"\xff\xfe", "", True, "untyped content"),
        (b"[1, 2]", JSON, False, "JSON list"),
        (body({"error": {"message": "model is loading"}}), JSON, False, "model is loading"),
        (body({"object": "list"}), JSON, False, "no choices (fields: object)"),
        (body({"choices": [{"message": "text"}]}), JSON, False, "choices[0] not a chat message"),
        (body({"choices": [{"message": {"content": 3}}]}), JSON, False, "choices[0]"),
    ],
)
def test_unusable_bodies_say_what_is_wrong(raw: bytes, content_type: str, retryable: bool,
                                           says: str) -> None:
    with pytest.raises(ChatBodyError) as info:
        parse_chat_body(raw, content_type, max_tokens=16)
    assert info.value.retryable is retryable and says in str(info.value)


def test_text_beyond_what_max_tokens_allows_is_refused() -> None:
    limit = 10 * MAX_CHARS_PER_TOKEN
    assert parse_chat_body(body(chat_completion("a" * limit)), JSON, 10).text == "a" * limit
    with pytest.raises(ChatBodyError, match=f"max_tokens=10 allows \\({limit}"):
        parse_chat_body(body(chat_completion("a" * (limit + 1))), JSON, 10)


@pytest.mark.parametrize(
    ("headers", "seconds"),
    [
        ({"retry-after": "2"}, 2.0),
        ({"retry-after": "0.5"}, 0.5),
        ({"retry-after-ms": "1500", "retry-after": "9"}, 1.5),
        ({"retry-after": "-3"}, 0.0),
        ({"retry-after": "soon"}, None),
        ({"retry-after": "nan"}, None),
        ({}, None),
    ],
)
def test_retry_after_reads_seconds_and_milliseconds(headers: dict[str, str],
                                                    seconds: float | None) -> None:
    assert retry_after(headers) == seconds


def test_retry_after_reads_an_http_date() -> None:
    later = email.utils.formatdate(time.time() + 30, usegmt=True)
    assert 25.0 <= (retry_after({"retry-after": later}) or 0.0) <= 31.0
    past = email.utils.formatdate(time.time() - 30, usegmt=True)
    assert retry_after({"retry-after": past}) == 0.0


class _Clock:
    """Simulated time: each attempt costs one second, each wait its length."""

    def __init__(self) -> None:
        self.now = 0.0
        self.waits: list[float] = []

    def sleep(self, seconds: float) -> None:
        self.waits.append(seconds)
        self.now += seconds

    def attempt(self) -> None:
        self.now += 1.0
        raise RetryableError("busy", status=429, retry_after=30.0)


def test_retry_after_is_honoured_up_to_the_cap() -> None:
    clock = _Clock()
    policy = RetryPolicy(max_retries=2, initial_delay=0.5, max_delay=4.0)
    with pytest.raises(RetryableError) as info:
        call_with_retries(clock.attempt, policy, sleep=clock.sleep, clock=lambda: clock.now)
    assert clock.waits == [4.0, 4.0] and info.value.attempts == 3
    assert not info.value.out_of_time and info.value.elapsed == 11.0


def test_the_budget_stops_before_a_wait_that_would_pass_it() -> None:
    clock = _Clock()
    policy = RetryPolicy(max_retries=10, initial_delay=0.5, max_delay=4.0, max_elapsed=8.0)
    with pytest.raises(RetryableError) as info:
        call_with_retries(clock.attempt, policy, sleep=clock.sleep, clock=lambda: clock.now)
    # attempt (1 s), wait 4 s, attempt (6 s elapsed): another 4 s wait would pass 8 s
    assert clock.waits == [4.0] and info.value.attempts == 2 and info.value.out_of_time


def test_a_budget_must_be_positive() -> None:
    with pytest.raises(ConfigError, match="max_elapsed=0"):
        RetryPolicy(max_elapsed=0)


def test_a_body_cap_must_be_positive() -> None:
    with pytest.raises(ConfigError, match="max_bytes=0"):
        body_limits_hook(max_bytes=0)
