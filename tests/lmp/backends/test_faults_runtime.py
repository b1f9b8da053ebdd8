"""Fault injection end to end: a failing endpoint through the LMP runtime and the benchmark.

An endpoint that keeps failing must make ``LMPRuntime.run`` end (bounded by the backend's
timeouts and retries, and guarded by :func:`within`) in a :class:`LLMError`, and make the
benchmark record the episode as failed and return, ready for the next one.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import NamedTuple

import pytest

from tests.lmp.backends.bounded import within
from tests.lmp.backends.fake_openai_server import FakeOpenAIServer, Reply
from voxposer.bench import EpisodeJob, EpisodeRecord, run_episode
from voxposer.errors import EndpointError, LLMError, LMPFailedError, VoxPoserError
from voxposer.lmp import LMPConfig, LMPRuntime, RecordingHandler, make_tabletop_scene
from voxposer.lmp.backends import LLMBackend, LLMConfig, make_backend

INSTRUCTION = "move to the left of the blue block"
GUARD_S = 60.0
PLAN = f"composer({INSTRUCTION!r})"
COMPOSE = ("movable = parse_query_obj('gripper')\n"
           f"affordance_map = get_affordance_map({INSTRUCTION!r})\n"
           "execute(movable, affordance_map=affordance_map)")


@pytest.fixture
def server() -> Iterator[FakeOpenAIServer]:
    with FakeOpenAIServer() as fake:
        yield fake


def openai_backend(server: FakeOpenAIServer) -> LLMBackend:
    """The backend as the CLI builds it (factory, config), without the response cache."""
    return make_backend(LLMConfig(backend="openai", model="fake-model", base_url=server.url,
                                  timeout=1.0, max_retries=1, total_timeout=10.0, cache=False))


class Ended(NamedTuple):
    """How a run against a scripted endpoint ended."""

    runtime: LMPRuntime
    handler: RecordingHandler
    error: VoxPoserError


def run(server: FakeOpenAIServer, *script: Reply) -> Ended:
    """Run the instruction against ``script``; it must end in a VoxPoserError."""
    server.script(*script)
    handler = RecordingHandler()
    runtime = LMPRuntime(make_tabletop_scene(), openai_backend(server), handler=handler,
                         config=LMPConfig(max_attempts=3))
    with pytest.raises(VoxPoserError) as info:
        within(GUARD_S, lambda: runtime.run(INSTRUCTION))
    runtime.backend.close()
    return Ended(runtime, handler, info.value)


@pytest.mark.parametrize("reply", [Reply.error(503), Reply.hang(30.0), Reply("cut"),
                                   Reply("truncated_json"), Reply.endless(delay=0.02)],
                         ids=["503", "hang", "cut", "truncated_json", "endless"])
def test_an_endpoint_that_keeps_failing_ends_the_run_in_an_llm_error(
        server: FakeOpenAIServer, reply: Reply) -> None:
    runtime, handler, err = run(server, reply)
    assert isinstance(err, EndpointError) and isinstance(err, LLMError)
    assert err.attempts == 2 and len(server.received) == 2  # max_retries=1: bounded
    assert server.url in str(err)
    assert runtime.llm_calls == 1 and not handler.requests  # nothing was executed


def test_a_failure_mid_run_ends_in_a_voxposer_error_naming_the_endpoint(
        server: FakeOpenAIServer) -> None:
    """The planner and composer answer, then the endpoint fails inside the composer's code: the
    run ends in the endpoint's error itself, with no self-correction on it."""
    _, handler, err = run(server, Reply.ok(PLAN), Reply.ok(COMPOSE), Reply.error(503))
    assert isinstance(err, EndpointError) and "HTTP 503" in str(err)
    assert _chain_has(err, EndpointError)
    assert len(server.received) == 2 + 2  # the two answers, then one request tried twice
    assert not handler.requests


def test_a_failure_mid_run_is_reported_as_the_llm_error(server: FakeOpenAIServer) -> None:
    _, _, err = run(server, Reply.ok(PLAN), Reply.ok(COMPOSE), Reply.error(503))
    assert isinstance(err, LLMError)  # not wrapped, not self-corrected on


def test_non_code_text_ends_in_a_program_error_after_self_correction(
        server: FakeOpenAIServer) -> None:
    runtime, _, err = run(server, Reply.ok("Sorry, as a language model I cannot move blocks."))
    assert isinstance(err, LMPFailedError) and not isinstance(err, LLMError)
    assert len(err.attempts) == 3 and "SyntaxError" in str(err)
    assert runtime.llm_calls == 3 == len(server.received)


@pytest.mark.timeout(300)  # a backstop; the backend's own timeouts bound the LLM calls
def test_the_benchmark_records_an_endpoint_failure_and_carries_on(
        server: FakeOpenAIServer, world: object) -> None:
    records: list[EpisodeRecord] = []
    for reply in (Reply.error(503), Reply.hang(30.0)):
        server.script(reply)
        job = EpisodeJob("move_to_region", "seen", len(records), llm="openai", max_time_s=5.0)
        records.append(run_episode(job, world, backend=openai_backend(server)))
    for rec, status in zip(records, ("HTTP 503", "no answer within 1 s"), strict=True):
        assert rec.error is not None or rec.program_error is not None
        assert not rec.success
        assert "EndpointError" in (rec.program_error or rec.error or "")
        assert status in (rec.program_error or rec.error or "")
    assert len(server.received) == 4  # two episodes × (1 try + 1 retry), none left hanging


def _chain_has(err: BaseException | None, kind: type[BaseException]) -> bool:
    while err is not None:
        if isinstance(err, kind):
            return True
        err = err.__cause__ or err.__context__
    return False
