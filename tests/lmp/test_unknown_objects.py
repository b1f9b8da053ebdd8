"""An object the scene lacks, on recorded programs (the replay backend, a test double): the error
names the query and the scene's objects, is what the model sees when it retries, and reaches the
caller as an UnknownObjectError instead of a chain of retries ending in a type complaint."""

from __future__ import annotations

from pathlib import Path

import pytest

from voxposer.errors import UnknownObjectError, UnresolvedObjectError
from voxposer.lmp import LMPConfig, LMPRuntime, ObjectView, RecordingHandler, make_tabletop_scene
from voxposer.lmp.backends.replay import ReplayBackend

RECORDINGS = Path(__file__).parent / "recordings" / "unknown_object.jsonl"


def _runtime() -> LMPRuntime:
    return LMPRuntime(make_tabletop_scene(), ReplayBackend(RECORDINGS),
                      handler=RecordingHandler(), config=LMPConfig(max_attempts=3))


def _calls(rt: LMPRuntime, lmp: str, query: str | None = None) -> list[dict]:
    return [e for e in rt.transcript.events if e["event"] == "llm_call" and e["lmp"] == lmp
            and query in (None, e["query"])]


def test_a_query_for_a_missing_object_names_it_and_the_scene() -> None:
    rt = _runtime()
    with pytest.raises(UnknownObjectError) as info:
        rt.run("push the unicorn to the left side of the table")
    err = info.value
    assert isinstance(err, UnresolvedObjectError)
    assert err.name == "unicorn" and err.lmp == "parse_query_obj" and err.query == "unicorn"
    assert set(err.known) == set(rt.scene.object_names)
    text = str(err)
    assert text.startswith("unknown object 'unicorn'; the scene has: ")
    assert "blue block" in text and "top drawer handle" in text and "table" in text
    assert "NoneType" not in text
    # planner, composer, and parse_query_obj twice: the model, shown the scene's objects,
    # answered "nothing" again, which settles it (its third, invented answer is never asked for)
    assert rt.llm_calls == 4
    retry = _calls(rt, "parse_query_obj")[1]["messages"][-1]["content"]
    assert "UnknownObjectError: unknown object 'unicorn'; the scene has: " in retry
    assert "NoneType" not in retry
    assert len(_calls(rt, "composer")) == 1  # the composer did not retry with another object
    assert rt.handler.requests == []  # nothing was executed


def test_an_unknown_name_given_to_detect_passes_through_every_enclosing_program() -> None:
    rt = _runtime()
    with pytest.raises(UnresolvedObjectError) as info:
        rt.run("move the gripper above the dragon")
    err = info.value
    assert err.name == "green dragon" and err.query == "dragon" and len(err.attempts) == 3
    assert "unknown object 'green dragon'; the scene has: " in str(err)
    assert "parse_query_obj('dragon') gave up after 3 attempt(s)" in str(err)
    retries = [c["messages"][-1]["content"] for c in _calls(rt, "parse_query_obj", "dragon")[1:]]
    assert "unknown object 'dragon'" in retries[0] and "blue block" in retries[0]
    # each of planner, composer and get_affordance_map was asked once; none retried
    assert [len(_calls(rt, lmp)) for lmp in ("planner", "composer", "get_affordance_map")] == \
        [1, 1, 1]
    assert len(_calls(rt, "parse_query_obj", "dragon")) == 3
    # parse_query_obj('gripper') names a scene object exactly: answered without the model
    assert rt.llm_calls == 6 and rt.handler.requests == []


def test_nothing_found_then_a_real_object_on_retry_is_accepted() -> None:
    rt = _runtime()
    block = rt.query("parse_query_obj", "the leftmost block")
    assert isinstance(block, ObjectView) and block.name.endswith("block")
    first_retry = _calls(rt, "parse_query_obj")[1]["messages"][-1]["content"]
    assert "unknown object 'the leftmost block'" in first_retry
    assert rt.code_cache[("parse_query_obj", "the leftmost block")].startswith("blocks = ")
