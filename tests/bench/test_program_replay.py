"""Replaying an episode's recorded programs: exact query first, then the LMP's next one."""

from __future__ import annotations

import pytest

from voxposer.bench.program_replay import QUERY_CHARS, RecordedProgramsBackend
from voxposer.errors import LLMError
from voxposer.lmp.backends.base import ChatMessage, LLMRequest


def _request(lmp: str, query: str) -> LLMRequest:
    return LLMRequest(messages=(ChatMessage("system", "prompt"), ChatMessage("user", query)),
                      prefix_id=lmp)


PROGRAMS = [
    {"lmp": "planner", "query": "# Query: push the blue block left", "code": "composer('a')"},
    {"lmp": "composer", "query": "# Query: a", "code": "execute(1)"},
    {"lmp": "composer", "query": "# Query: b", "code": "execute(2)"},
]


def test_each_request_gets_the_program_written_for_it() -> None:
    backend = RecordedProgramsBackend(PROGRAMS)
    assert backend.complete(_request("composer", "# Query: b")).text == "execute(2)"
    assert backend.complete(_request("planner", "# Query: push the blue block left")).text \
        == "composer('a')"
    assert backend.complete(_request("composer", "# Query: a")).text == "execute(1)"
    assert backend.loose == 0


def test_a_query_the_original_never_asked_gets_its_lmps_next_program_counted_loose() -> None:
    backend = RecordedProgramsBackend(PROGRAMS)
    assert backend.complete(_request("composer", "# Query: c")).text == "execute(1)"
    assert backend.loose == 1
    assert backend.complete(_request("composer", "# Query: b")).text == "execute(2)"
    with pytest.raises(LLMError, match="no program left for composer"):
        backend.complete(_request("composer", "# Query: a"))


def test_long_queries_match_on_their_recorded_tail() -> None:
    long = "x" * 1000 + "# Query: a"
    backend = RecordedProgramsBackend([{"lmp": "composer", "query": long[-QUERY_CHARS:],
                                        "code": "ok"}])
    assert backend.complete(_request("composer", long)).text == "ok"
    assert backend.loose == 0


def test_a_malformed_recording_is_refused() -> None:
    with pytest.raises(LLMError, match="recorded program 0 needs the keys"):
        RecordedProgramsBackend([{"lmp": "planner", "query": "q"}])
