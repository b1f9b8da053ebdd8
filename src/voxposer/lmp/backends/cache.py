"""A persistent sqlite cache of LLM responses, and a backend wrapper that consults it.

Keys are :meth:`LLMRequest.key` of (backend name, model, full request), so a different model,
prompt, temperature or stop list is a different entry. The database runs in WAL mode with a busy
timeout, so several threads and processes may share it. Only successful responses are stored.
"""

from __future__ import annotations

import itertools
import json
import logging
import sqlite3
import threading
import time
from collections.abc import Sequence
from dataclasses import asdict, replace
from pathlib import Path

from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse

log = logging.getLogger(__name__)

#: How long opening or writing waits for another process's lock [s].
_BUSY_TIMEOUT_S = 30.0

_SCHEMA = """
CREATE TABLE IF NOT EXISTS responses (
    key TEXT PRIMARY KEY,
    backend TEXT NOT NULL,
    model TEXT NOT NULL,
    request TEXT NOT NULL,
    text TEXT NOT NULL,
    prompt_tokens INTEGER NOT NULL,
    completion_tokens INTEGER NOT NULL,
    seconds REAL NOT NULL,
    created REAL NOT NULL
)
"""


class ResponseCache:
    """Responses on disk, keyed by backend + model + request.

    Args:
        path: the sqlite file (created with its directory when missing).
    """

    def __init__(self, path: Path) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._lock = threading.Lock()
        self._conn = sqlite3.connect(self.path, timeout=_BUSY_TIMEOUT_S, check_same_thread=False)
        deadline = time.monotonic() + _BUSY_TIMEOUT_S
        for attempt in itertools.count():
            try:
                with self._lock:
                    self._conn.execute("PRAGMA journal_mode=WAL")
                    self._conn.execute("PRAGMA synchronous=NORMAL")
                    self._conn.execute(_SCHEMA)
                    self._conn.commit()
                break
            except sqlite3.OperationalError as err:
                # two processes opening a new file at once both read it and then both ask to
                # turn it to WAL: sqlite answers one "locked" at once, without waiting (a
                # deadlock otherwise); the other's conversion is over in milliseconds
                if "locked" not in str(err) or time.monotonic() > deadline:
                    raise
                self._conn.rollback()
                time.sleep(min(0.5, 0.01 * 2 ** attempt))

    def get(self, key: str) -> LLMResponse | None:
        """The stored response for ``key`` (marked ``cached=True``), or None."""
        with self._lock:
            row = self._conn.execute(
                "SELECT model, text, prompt_tokens, completion_tokens, seconds "
                "FROM responses WHERE key = ?",
                (key,),
            ).fetchone()
        if row is None:
            return None
        model, text, prompt_tokens, completion_tokens, seconds = row
        return LLMResponse(
            text=text,
            model=model,
            prompt_tokens=prompt_tokens,
            completion_tokens=completion_tokens,
            seconds=0.0,
            cached=True,
            extra={"original_seconds": seconds},
        )

    def put(self, key: str, backend: str, request: LLMRequest, response: LLMResponse) -> None:
        """Store ``response`` under ``key`` (replacing an older entry)."""
        with self._lock:
            self._conn.execute(
                "INSERT OR REPLACE INTO responses VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    key,
                    backend,
                    response.model,
                    json.dumps(asdict(request), ensure_ascii=False),
                    response.text,
                    response.prompt_tokens,
                    response.completion_tokens,
                    response.seconds,
                    time.time(),
                ),
            )
            self._conn.commit()

    def __len__(self) -> int:
        with self._lock:
            (count,) = self._conn.execute("SELECT COUNT(*) FROM responses").fetchone()
        return int(count)

    def clear(self) -> None:
        """Delete every entry."""
        with self._lock:
            self._conn.execute("DELETE FROM responses")
            self._conn.commit()

    def close(self) -> None:
        """Close the database connection."""
        with self._lock:
            self._conn.close()


class CachedBackend(LLMBackend):
    """Wraps ``inner``: answers from ``cache`` when it can, else asks ``inner`` and stores.

    Args:
        inner: the backend that produces responses on a miss.
        cache: the response store.
    """

    def __init__(self, inner: LLMBackend, cache: ResponseCache) -> None:
        self.inner = inner
        self.cache = cache
        self.name = inner.name

    @property
    def model(self) -> str:
        return self.inner.model

    def complete(self, request: LLMRequest) -> LLMResponse:
        key = request.key(self.inner.name, self.inner.model)
        start = time.perf_counter()
        hit = self.cache.get(key)
        if hit is not None:
            log.debug("response cache hit %s", key[:12])
            return replace(hit, seconds=time.perf_counter() - start)
        response = self.inner.complete(request)
        if not response.cached:
            self.cache.put(key, self.inner.name, request, response)
        return response

    def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        """Hits from the cache; the misses asked of ``inner`` together, then stored."""
        keys = [r.key(self.inner.name, self.inner.model) for r in requests]
        out: list[LLMResponse | None] = []
        for key in keys:
            hit = self.cache.get(key)
            out.append(None if hit is None else replace(hit, seconds=0.0))
        misses = [k for k, r in enumerate(out) if r is None]
        for k, response in zip(misses, self.inner.complete_many([requests[k] for k in misses]),
                               strict=True):
            if not response.cached:
                self.cache.put(keys[k], self.inner.name, requests[k], response)
            out[k] = response
        return [r for r in out if r is not None]

    def close(self) -> None:
        self.inner.close()
        self.cache.close()
