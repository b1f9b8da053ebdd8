"""Map programs asked together: which calls a composer program makes with literal queries, and
that asking them ahead changes no program, only how the backend is asked."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from voxposer.lmp import LMPConfig, LMPRuntime, RecordingHandler, make_tabletop_scene
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.backends.replay import ReplayBackend
from voxposer.lmp.prefetch import map_queries

RECORDINGS = Path(__file__).parent / "recordings"
INSTRUCTION = "move to the left of the blue block while staying away from the green block"


def test_literal_map_calls_are_found_in_order_once() -> None:
    code = (
        "movable = parse_query_obj('gripper')\n"
        "avoidance_map = get_avoidance_map('10cm around the green block')\n"
        "affordance_map = get_affordance_map('left of the blue block')\n"
        "again = get_avoidance_map('10cm around the green block')\n"
        "computed = get_velocity_map(f'{speed} everywhere')\n"
        "named = get_gripper_map(query='open everywhere')\n"
        "execute(movable, affordance_map=affordance_map, avoidance_map=avoidance_map)\n"
    )
    assert map_queries(code) == [("get_avoidance_map", "10cm around the green block"),
                                 ("get_affordance_map", "left of the blue block")]
    assert map_queries("get_affordance_map('x'") == []  # does not parse
    assert map_queries("composer('push it')\nparse_query_obj('red block')") == []


class Batches(LLMBackend):
    """Answers through ``inner`` and keeps how it was asked: one request, or several together
    (a test double)."""

    name = "batches"

    def __init__(self, inner: LLMBackend) -> None:
        self.inner = inner
        self.asked: list[list[str]] = []  # the LMP of each request, per call

    @property
    def model(self) -> str:
        return self.inner.model

    def complete(self, request: LLMRequest) -> LLMResponse:
        self.asked.append([request.prefix_id or ""])
        return self.inner.complete(request)

    def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        self.asked.append([r.prefix_id or "" for r in requests])
        return [self.inner.complete(r) for r in requests]


def run(batch: bool) -> tuple[LMPRuntime, Batches]:
    backend = Batches(ReplayBackend(RECORDINGS / "closed_loop.jsonl"))
    rt = LMPRuntime(make_tabletop_scene(), backend, handler=RecordingHandler(),
                    config=LMPConfig(batch_map_calls=batch))
    rt.run(INSTRUCTION)
    return rt, backend


def test_asking_together_is_off_by_default() -> None:
    assert LMPConfig().batch_map_calls is False


def test_the_composer_s_map_calls_are_asked_together_with_the_same_programs() -> None:
    batched, asked = run(batch=True)
    one_by_one, single = run(batch=False)
    maps = ["get_affordance_map", "get_avoidance_map", "get_velocity_map"]
    assert asked.asked == [["planner"], ["composer"], maps]
    assert all(len(call) == 1 for call in single.asked)
    assert batched.code_cache == one_by_one.code_cache  # the same programs
    assert batched.llm_calls == one_by_one.llm_calls  # a held response counts as its call
    first = batched.handler.requests[0]  # type: ignore[attr-defined]
    again = one_by_one.handler.requests[0]  # type: ignore[attr-defined]
    assert sorted(first.maps) == sorted(again.maps) == ["affordance_map", "avoidance_map",
                                                        "velocity_map"]
    for name in first.maps:  # the maps the executor receives are the same
        assert (first.maps[name]() == again.maps[name]()).all()
    held = [e for e in batched.transcript.events if e["event"] == "llm_call" and e["batched"]]
    assert [e["lmp"] for e in held] == maps
