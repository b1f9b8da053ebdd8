"""LMP runtime on recorded programs: composition, closed-loop re-evaluation, self-correction."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from voxposer.errors import LLMError, LMPFailedError, UnknownObjectError
from voxposer.lmp import (
    LMPConfig,
    LMPRuntime,
    ObjectView,
    RecordingHandler,
    Transcript,
    ValueMapProgram,
    make_tabletop_scene,
)
from voxposer.lmp.backends.replay import ReplayBackend

RECORDINGS = Path(__file__).parent / "recordings"
INSTRUCTION = "move to the left of the blue block while staying away from the green block"


def runtime(name: str, tmp_path: Path | None = None, **config: object) -> LMPRuntime:
    transcript = Transcript(tmp_path / "run.jsonl" if tmp_path else None)
    return LMPRuntime(make_tabletop_scene(), ReplayBackend(RECORDINGS / name),
                      handler=RecordingHandler(), config=LMPConfig(**config),
                      transcript=transcript)


def test_composer_hands_re_evaluable_maps_to_the_executor() -> None:
    rt = runtime("closed_loop.jsonl")
    rt.run(INSTRUCTION)
    executor = rt.handler
    assert isinstance(executor, RecordingHandler)
    assert len(executor.requests) == 1
    request = executor.requests[0]
    assert set(request.maps) == {"affordance_map", "avoidance_map", "velocity_map"}
    assert all(isinstance(fn, ValueMapProgram) for fn in request.maps.values())
    evaluated = executor.evaluated[0]
    assert isinstance(evaluated["movable"], ObjectView) and evaluated["movable"].name == "gripper"
    blue = rt.api.detect("blue block")
    target = np.argwhere(evaluated["affordance_map"] > 0)
    assert target.shape == (1, 3)
    # 5 cm beyond the -y face of the 5 cm block: 7.5 cm from the centre along -y
    assert target[0, 1] == pytest.approx(blue.position[1] - 7.5, abs=1)
    green = rt.api.detect("green block").position
    assert evaluated["avoidance_map"][tuple(green)] == 1
    assert evaluated["velocity_map"][tuple(green)] == 0.5


def test_re_evaluation_follows_a_moved_object_without_llm_calls() -> None:
    rt = runtime("closed_loop.jsonl")
    rt.run(INSTRUCTION)
    calls = rt.llm_calls
    afford = rt.handler.requests[0].maps["affordance_map"]
    before = np.argwhere(afford() > 0)[0]
    rt.scene.move("blue block", (0.10, 0.05, 0.0))  # type: ignore[attr-defined]
    after = np.argwhere(afford() > 0)[0]
    assert (after - before).tolist() == [10, 5, 0]
    assert rt.llm_calls == calls
    assert rt.backend.calls == calls  # type: ignore[attr-defined]


def test_self_correction_feeds_the_error_back(tmp_path: Path) -> None:
    rt = runtime("self_correction.jsonl", tmp_path)
    out = rt.query("get_affordance_map", "a point 5cm above the yellow block")
    yellow = rt.api.detect("yellow block")
    target = np.argwhere(out > 0)[0]
    assert target[2] == pytest.approx(yellow.aabb[1][2] + 5, abs=1)
    calls = [e for e in rt.transcript.events if e["event"] == "llm_call"
             and e["lmp"] == "get_affordance_map"]
    assert [c["attempt"] for c in calls] == [1, 2]
    assert "IndexError" in calls[1]["messages"][-1]["content"]  # the error was shown
    execs = [e for e in rt.transcript.events if e["event"] == "exec"
             and e["lmp"] == "get_affordance_map"]
    assert [e["ok"] for e in execs] == [False, True]


@pytest.mark.parametrize("lmp, query, fed_back", [
    ("get_avoidance_map", "5cm around the pink block", "unchanged"),
    ("parse_query_obj", "the violet sphere", "unknown object 'violet sphere'"),
    ("get_velocity_map", "half speed everywhere", "import"),
    ("get_affordance_map", "a point 3cm behind the red block", "copy it first"),
])
def test_sanity_and_refusal_errors_trigger_a_retry(lmp: str, query: str, fed_back: str) -> None:
    rt = runtime("self_correction.jsonl")
    rt.query(lmp, query)
    calls = [e for e in rt.transcript.events if e["event"] == "llm_call" and e["lmp"] == lmp]
    assert len(calls) == 2
    assert fed_back in calls[1]["messages"][-1]["content"]


def test_unknown_object_lists_the_scene() -> None:
    rt = runtime("self_correction.jsonl")
    with pytest.raises(UnknownObjectError, match="blue block"):
        rt.api.detect("violet sphere")


def test_giving_up_after_max_attempts_keeps_every_attempt() -> None:
    rt = runtime("self_correction.jsonl", max_attempts=3)
    with pytest.raises(LMPFailedError) as info:
        rt.query("get_gripper_map", "close everywhere")
    assert len(info.value.attempts) == 3
    assert all("SyntaxError" in a["error"] for a in info.value.attempts)


def test_missing_recording_names_lmp_and_query() -> None:
    rt = runtime("closed_loop.jsonl")
    with pytest.raises(LLMError, match=r"get_rotation_map\('top-down'\)"):
        rt.query("get_rotation_map", "top-down")


def test_transcript_is_jsonl_written_incrementally(tmp_path: Path) -> None:
    rt = runtime("closed_loop.jsonl", tmp_path)
    rt.run(INSTRUCTION)
    lines = (tmp_path / "run.jsonl").read_text().splitlines()
    events = [json.loads(line) for line in lines]
    kinds = {e["event"] for e in events}
    # the plan states no post-condition: its "staying away" is derived (plan_completed) and
    # evaluated (intent)
    assert kinds == {"prompt", "llm_call", "exec", "execute", "resolved", "plan_completed",
                     "intent"}
    llm = [e for e in events if e["event"] == "llm_call"]
    resolved = [e for e in events if e["event"] == "resolved"]
    # the parse_query_obj queries that name a scene object exactly need no LLM call
    assert {e["name"] for e in resolved} >= {"blue block", "green block"}
    assert len(llm) == rt.llm_calls == 8 - len(resolved)
    assert not any(e["event"] == "llm_call" and e["lmp"] == "parse_query_obj"
                   and e["query"] in {r["query"] for r in resolved} for e in events)
    assert all(e["response"] for e in llm)
    assert any(e["event"] == "exec" and "point_beside" in e["code"] for e in events)


def test_each_execute_call_is_in_the_transcript_with_its_outcome() -> None:
    """Succeeded or failed, what the robot did for an ``execute`` call is a transcript event."""

    class Refusing(RecordingHandler):
        def execute(self, request):
            from voxposer.errors import ExecutionFailedError

            raise ExecutionFailedError(request.subtask, "stalled", "the arm was blocked")

    rt = runtime("closed_loop.jsonl")
    rt.run(INSTRUCTION)
    done = [e for e in rt.transcript.events if e["event"] == "execute"]
    assert len(done) == 1 and done[0]["success"] is True
    failing = LMPRuntime(make_tabletop_scene(), ReplayBackend(RECORDINGS / "closed_loop.jsonl"),
                         handler=Refusing())
    with pytest.raises(LMPFailedError):
        failing.run(INSTRUCTION)
    failed = [e for e in failing.transcript.events if e["event"] == "execute"]
    assert len(failed) == 1 and failed[0]["success"] is False
    assert "the arm was blocked" in failed[0]["message"]


def test_an_interrupt_inside_a_program_stops_the_run_instead_of_failing_it(monkeypatch) -> None:
    # a stop signal raised while compiled perception code returns arrives as a SystemError
    rt = runtime("closed_loop.jsonl")
    scene = rt.api.scene
    real_detect = scene.detect

    def interrupted(name: str):
        if name == "green block":
            try:
                raise KeyboardInterrupt
            except KeyboardInterrupt as stop:
                raise SystemError("CPUDispatcher(...) returned a result with an exception "
                                  "set") from stop
        return real_detect(name)

    monkeypatch.setattr(scene, "detect", interrupted)
    with pytest.raises(KeyboardInterrupt):
        rt.run(INSTRUCTION)
