"""Limits on how long an HTTP response body may keep arriving and how large it may grow.

An HTTP client's read timeout bounds each wait for the next bytes, not the whole body: a server
that sends a few bytes every second (or an endless body as fast as it can) never trips it. The
hook from :func:`body_limits_hook` wraps every response of an ``httpx2.Client`` (the ``openai``
SDK's transport) so that its body must be complete within the request's read timeout [s] of the
headers arriving, and may hold at most ``max_bytes`` bytes as sent. Going past the deadline
raises :class:`BodyDeadlineError` (an ``httpx2.ReadTimeout``, so the SDK reports a timeout);
going past the size raises :class:`BodyTooLargeError`, which the SDK passes through unchanged.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator

import httpx2

from voxposer.errors import ConfigError

#: default cap of one response body [bytes]; a chat completion of 8192 tokens is ~100 kB
DEFAULT_MAX_BODY_BYTES = 8 * 1024 * 1024


class BodyDeadlineError(httpx2.ReadTimeout):
    """The response body was still arriving when its time was up."""


class BodyTooLargeError(Exception):
    """The response body grew past the size cap (an endless or runaway answer).

    Attributes:
        max_bytes: the cap [bytes].
        status: the response's HTTP status.
    """

    def __init__(self, max_bytes: int, status: int) -> None:
        self.max_bytes = max_bytes
        self.status = status
        super().__init__(f"the body of an HTTP {status} response exceeded {max_bytes} bytes")


def body_limits_hook(max_bytes: int = DEFAULT_MAX_BODY_BYTES,
                     default_timeout: float = 120.0) -> Callable[[httpx2.Response], None]:
    """A response event hook bounding each body's duration and size.

    Args:
        max_bytes: most bytes a body may hold as sent (before any decompression).
        default_timeout: the body's time limit [s] when the request carries no read timeout.
    """
    if max_bytes < 1:
        raise ConfigError(f"max_bytes={max_bytes} must be >= 1")

    def hook(response: httpx2.Response) -> None:
        if not isinstance(response.stream, httpx2.SyncByteStream):  # an async client's
            return
        read = response.request.extensions.get("timeout", {}).get("read")
        seconds = float(read) if read is not None else default_timeout
        response.stream = _BoundedStream(response.stream, response, seconds, max_bytes)

    return hook


class _BoundedStream(httpx2.SyncByteStream):
    """A response stream that stops at a deadline or a size cap."""

    def __init__(self, inner: httpx2.SyncByteStream, response: httpx2.Response, seconds: float,
                 max_bytes: int) -> None:
        self._inner = inner
        self._request = response.request
        self._status = response.status_code
        self._seconds = seconds
        self._deadline = time.monotonic() + seconds
        self._max_bytes = max_bytes

    def __iter__(self) -> Iterator[bytes]:
        received = 0
        for chunk in self._inner:
            received += len(chunk)
            if received > self._max_bytes:
                raise BodyTooLargeError(self._max_bytes, self._status)
            if time.monotonic() > self._deadline:
                raise BodyDeadlineError(
                    f"the response body was still arriving {self._seconds:g} s after its "
                    f"headers ({received} bytes so far)", request=self._request)
            yield chunk

    def close(self) -> None:
        self._inner.close()
