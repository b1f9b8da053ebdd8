"""Bounded retries with exponential backoff for calls to remote endpoints.

A retry waits ``initial_delay`` [s], doubling each time up to ``max_delay``; a server's
Retry-After hint is honoured up to that same cap. ``max_retries`` bounds the attempts and the
optional ``max_elapsed`` bounds the whole call: no wait (and so no further attempt) starts that
would end past it.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TypeVar

from voxposer.errors import ConfigError

log = logging.getLogger(__name__)
T = TypeVar("T")


class RetryableError(Exception):
    """Raised by an attempt that may succeed when repeated (refused, timeout, 429, 5xx).

    Attributes:
        status: HTTP status code, or None when no response arrived.
        retry_after: the server's Retry-After hint [s], if any.
        attempts: attempts made when it was finally raised (set by :func:`call_with_retries`).
        elapsed: seconds from the first attempt until it was finally raised [s] (set likewise).
        out_of_time: True when the retries stopped because the next one would pass
            ``RetryPolicy.max_elapsed`` rather than because ``max_retries`` were used up.
    """

    def __init__(self, message: str, status: int | None = None,
                 retry_after: float | None = None) -> None:
        self.status = status
        self.retry_after = retry_after
        self.attempts = 0
        self.elapsed = 0.0
        self.out_of_time = False
        super().__init__(message)


@dataclass(frozen=True)
class RetryPolicy:
    """How often and how patiently to retry.

    Attributes:
        max_retries: retries after the first attempt (0 = try once).
        initial_delay: wait before the first retry [s]; doubles each time.
        max_delay: cap of one wait [s] (also caps a server's Retry-After).
        max_elapsed: time budget of the whole call, attempts and waits together [s]; None =
            bounded only by the attempts' own timeouts and the waits.
    """

    max_retries: int = 3
    initial_delay: float = 0.5
    max_delay: float = 8.0
    max_elapsed: float | None = None

    def __post_init__(self) -> None:
        if self.max_retries < 0:
            raise ConfigError(f"max_retries={self.max_retries} must be >= 0")
        if self.initial_delay < 0:
            raise ConfigError(f"initial_delay={self.initial_delay} s must be >= 0")
        if self.max_delay < self.initial_delay:
            raise ConfigError(
                f"max_delay={self.max_delay} s must be >= initial_delay={self.initial_delay} s"
            )
        if self.max_elapsed is not None and not self.max_elapsed > 0:
            raise ConfigError(f"max_elapsed={self.max_elapsed} s must be > 0 (or None)")

    def delay(self, retry: int, retry_after: float | None = None) -> float:
        """Wait before retry number ``retry`` (0-based) [s]."""
        backoff = min(self.max_delay, self.initial_delay * (2.0**retry))
        if retry_after is not None:
            backoff = max(backoff, min(self.max_delay, retry_after))
        return backoff


def call_with_retries(
    attempt: Callable[[], T],
    policy: RetryPolicy,
    sleep: Callable[[float], None] = time.sleep,
    clock: Callable[[], float] = time.monotonic,
) -> tuple[T, int]:
    """Run ``attempt`` until it succeeds, the retries are used up, or the time budget is.

    Args:
        attempt: one try; raises :class:`RetryableError` when trying again may help.
        policy: how often and how long to retry.
        sleep: waits the given seconds (injectable for tests).
        clock: monotonic time [s] (injectable for tests).

    Returns:
        (result, number of attempts made).

    Raises:
        RetryableError: the last attempt's error, with ``attempts``, ``elapsed`` and
            ``out_of_time`` set on it, once ``policy.max_retries`` retries have failed or the
            next wait would end past ``policy.max_elapsed``. Other exceptions propagate at once.
    """
    start = clock()
    retry = 0
    while True:
        try:
            return attempt(), retry + 1
        except RetryableError as exc:
            elapsed = clock() - start
            wait = policy.delay(retry, exc.retry_after)
            budget = policy.max_elapsed
            out_of_time = budget is not None and elapsed + wait >= budget
            if retry >= policy.max_retries or out_of_time:
                exc.attempts, exc.elapsed = retry + 1, elapsed
                exc.out_of_time = out_of_time and retry < policy.max_retries
                raise
            log.warning(
                "attempt %d/%d failed (%s); retrying in %.1f s",
                retry + 1,
                policy.max_retries + 1,
                exc,
                wait,
            )
            sleep(wait)
            retry += 1
