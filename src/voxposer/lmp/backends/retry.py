"""Bounded retries with exponential backoff for calls to remote endpoints."""

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
    """

    def __init__(self, message: str, status: int | None = None, retry_after: float | None = None):
        self.status = status
        self.retry_after = retry_after
        self.attempts = 0
        super().__init__(message)


@dataclass(frozen=True)
class RetryPolicy:
    """How often and how patiently to retry.

    Attributes:
        max_retries: retries after the first attempt (0 = try once).
        initial_delay: wait before the first retry [s]; doubles each time.
        max_delay: cap of one wait [s] (also caps a server's Retry-After).
    """

    max_retries: int = 3
    initial_delay: float = 0.5
    max_delay: float = 8.0

    def __post_init__(self) -> None:
        if self.max_retries < 0:
            raise ConfigError(f"max_retries={self.max_retries} must be >= 0")
        if self.initial_delay < 0:
            raise ConfigError(f"initial_delay={self.initial_delay} s must be >= 0")
        if self.max_delay < self.initial_delay:
            raise ConfigError(
                f"max_delay={self.max_delay} s must be >= initial_delay={self.initial_delay} s"
            )

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
) -> tuple[T, int]:
    """Run ``attempt`` until it succeeds or the retries are used up.

    Returns:
        (result, number of attempts made).

    Raises:
        RetryableError: the last attempt's error, with ``attempts`` set on it, once
            ``policy.max_retries`` retries have failed. Other exceptions propagate at once.
    """
    retry = 0
    while True:
        try:
            return attempt(), retry + 1
        except RetryableError as exc:
            if retry >= policy.max_retries:
                exc.attempts = retry + 1
                raise
            wait = policy.delay(retry, exc.retry_after)
            log.warning(
                "attempt %d/%d failed (%s); retrying in %.1f s",
                retry + 1,
                policy.max_retries + 1,
                exc,
                wait,
            )
            sleep(wait)
            retry += 1
