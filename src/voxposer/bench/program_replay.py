"""Replays the programs an episode's language model wrote, for counterfactual re-runs.

A benchmark record keeps every program its LLM wrote, in call order, as ``{"lmp", "query",
"code"}`` (:class:`~voxposer.bench.episode.CountingBackend`: ``lmp`` is the request's prefix id,
``query`` the last 300 characters of its last message). The error breakdown
(:mod:`voxposer.bench.breakdown`) re-runs a failed episode with one component replaced while
keeping what the model wrote; :class:`RecordedProgramsBackend` serves it. A request is answered
by the first unused recording of its LMP with the same query; when the re-run asks something
the original run did not (another perception names another object, a planner reports another
failure), by the next unused recording of its LMP in order — counted in ``loose``, since the
answer was written for another question. A request of an LMP with no recording left raises
LLMError naming it.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

from voxposer.errors import LLMError
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse

#: characters of a request's last message a record keeps as its query.
QUERY_CHARS = 300


class RecordedProgramsBackend(LLMBackend):
    """Serves an episode's recorded programs (see the module docs).

    Attributes:
        loose: requests answered by order rather than by an identical query.
    """

    name = "recorded-programs"

    def __init__(self, programs: Sequence[dict[str, Any]], model: str = "recorded") -> None:
        for k, p in enumerate(programs):
            if not isinstance(p, dict) or not {"lmp", "query", "code"} <= set(p):
                raise LLMError(f"recorded program {k} needs the keys lmp, query and code; got "
                               f"{sorted(p) if isinstance(p, dict) else type(p).__name__}")
        self._programs = [dict(p) for p in programs]
        self._used = [False] * len(self._programs)
        self._model = model
        self.loose = 0

    @property
    def model(self) -> str:
        return self._model

    def complete(self, request: LLMRequest) -> LLMResponse:
        start = time.monotonic()
        lmp = request.prefix_id or ""
        query = request.messages[-1].content[-QUERY_CHARS:] if request.messages else ""
        index = self._find(lmp, query)
        if index is None:
            index = self._find(lmp, None)
            if index is None:
                raise LLMError(f"recorded programs: no program left for {lmp or '<no lmp>'}"
                               f"({query[-80:]!r}); the re-run asked more than the original")
            self.loose += 1
        self._used[index] = True
        return LLMResponse(text=str(self._programs[index]["code"]), model=self._model,
                           seconds=time.monotonic() - start, cached=True)

    def _find(self, lmp: str, query: str | None) -> int | None:
        for k, p in enumerate(self._programs):
            if not self._used[k] and p["lmp"] == lmp and (query is None or p["query"] == query):
                return k
        return None


__all__ = ["QUERY_CHARS", "RecordedProgramsBackend"]
