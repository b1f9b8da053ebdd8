"""Replay and record: a test double that serves recorded responses, and a recorder.

:class:`ReplayBackend` is a **test double**: it answers only requests it has a recording for and
raises :class:`~voxposer.errors.LLMError` naming the LMP and query otherwise; it never falls back
to a model. Recordings are JSON lines (or a JSON list) of entries of two forms:

* exact, as written by :class:`RecordingBackend`:
  ``{"key": "<LLMRequest.key>", "backend": "...", "model": "...", "lmp": "...", "query": "...",
  "attempt": 1, "response": "..."}`` — matched by the sha256 of the whole request;
* hand-written, for tests: ``{"lmp": "get_affordance_map", "query": "...", "responses":
  ["<attempt 1>", "<attempt 2>"]}`` (or ``"response"`` with an optional ``"attempt"``) — matched by
  the LMP (the request's ``prefix_id``; for an "unseen instruction" fold's prefix id such as
  ``composer~push_to_pos``, an entry for exactly that id, else for its LMP ``composer``), the
  query and the self-correction attempt.
"""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from voxposer.errors import LLMError
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.prompt import request_query
from voxposer.lmp.prompt_tags import lmp_of


def load_recordings(path: str | Path) -> list[dict[str, Any]]:
    """Entries of a recordings file (JSONL, or a JSON list)."""
    p = Path(path)
    if not p.is_file():
        raise LLMError(f"recordings file {p} does not exist")
    text = p.read_text(encoding="utf-8")
    if text.lstrip().startswith("["):
        entries = json.loads(text)
    else:
        entries = []
        for n, line in enumerate(text.splitlines(), 1):
            if line.strip() and not line.lstrip().startswith("//"):
                try:
                    entries.append(json.loads(line))
                except json.JSONDecodeError as exc:
                    raise LLMError(f"{p}:{n}: not valid JSON: {exc}") from exc
    if not all(isinstance(e, dict) for e in entries):
        raise LLMError(f"{p}: every recording must be a JSON object")
    return entries


class ReplayBackend(LLMBackend):
    """Serves recorded responses (a test double; see the module doc).

    Attributes:
        calls: number of requests answered.
    """

    name = "replay"

    def __init__(self, recordings: str | Path | list[dict[str, Any]], model: str | None = None
                 ) -> None:
        entries = recordings if isinstance(recordings, list) else load_recordings(recordings)
        self.source = "<list>" if isinstance(recordings, list) else str(recordings)
        self._exact: dict[str, str] = {}
        self._by_query: dict[tuple[str, str, int], str] = {}
        self._origin: set[tuple[str, str]] = set()
        for e in entries:
            if "key" in e:
                self._exact[str(e["key"])] = str(e["response"])
                self._origin.add((str(e.get("backend", "")), str(e.get("model", ""))))
            responses = e.get("responses", [e["response"]] if "response" in e else [])
            first = int(e.get("attempt", 1))
            for k, text in enumerate(responses):
                self._by_query[(str(e.get("lmp", "")), str(e.get("query", "")), first + k)] = text
        self._model = model or next((m for _, m in sorted(self._origin) if m), "replay")
        self.calls = 0

    @property
    def model(self) -> str:
        return self._model

    def complete(self, request: LLMRequest) -> LLMResponse:
        start = time.monotonic()
        for backend, model in sorted(self._origin):
            text = self._exact.get(request.key(backend, model))
            if text is not None:
                break
        else:
            query, attempt = request_query(request.messages)
            text = self._by_query.get((request.prefix_id or "", query, attempt))
            if text is None:  # a fold's prefix id ("composer~push_to_pos"): its LMP's entry
                text = self._by_query.get((lmp_of(request.prefix_id), query, attempt))
            if text is None:
                raise LLMError(
                    f"replay: no recording for {request.prefix_id}({query!r}) attempt {attempt} "
                    f"in {self.source}; record it with --record (RecordingBackend)")
        self.calls += 1
        return LLMResponse(text=text, model=self._model, seconds=time.monotonic() - start,
                           cached=True)


class RecordingBackend(LLMBackend):
    """Wraps another backend and appends every exchange to a recordings file (JSONL)."""

    name = "recording"

    def __init__(self, inner: LLMBackend, path: str | Path) -> None:
        self.inner = inner
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._lock = threading.Lock()

    @property
    def model(self) -> str:
        return self.inner.model

    def complete(self, request: LLMRequest) -> LLMResponse:
        return self._record(request, self.inner.complete(request))

    def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        responses = self.inner.complete_many(requests)
        return [self._record(q, r) for q, r in zip(requests, responses, strict=True)]

    def _record(self, request: LLMRequest, response: LLMResponse) -> LLMResponse:
        query, attempt = request_query(request.messages)
        entry = {"key": request.key(self.inner.name, self.inner.model), "backend": self.inner.name,
                 "model": self.inner.model, "lmp": lmp_of(request.prefix_id), "query": query,
                 "attempt": attempt, "response": response.text}
        with self._lock, self.path.open("a", encoding="utf-8") as fh:
            fh.write(json.dumps(entry, ensure_ascii=False) + "\n")
        return response

    def close(self) -> None:
        self.inner.close()
