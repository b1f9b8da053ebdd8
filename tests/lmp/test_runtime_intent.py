"""The runtime's clause checklist and intent checks, on recorded programs (replay backend)."""

from __future__ import annotations

import json
from pathlib import Path

from voxposer.lmp import LMPConfig, LMPRuntime, RecordingHandler, Transcript, make_tabletop_scene
from voxposer.lmp.backends.replay import ReplayBackend
from voxposer.lmp.prompt import RETRY_PREFIX

RECORDINGS = Path(__file__).parent / "recordings" / "closed_loop.jsonl"
INSTRUCTION = "move to the left of the blue block while staying away from the green block"
FULL = "composer('move to the left of the blue block while staying 5cm away from the green block')"
DROPPED = "composer('move to the left of the blue block')"


def entries(*planner: str) -> list[dict]:
    rows = [json.loads(line) for line in RECORDINGS.read_text().splitlines()
            if line.startswith("{")]
    rows = [r for r in rows if r["lmp"] != "planner"]
    dropped = {"lmp": "composer", "query": DROPPED[10:-2], "responses": [
        "movable = parse_query_obj('gripper')\n"
        "affordance_map = get_affordance_map('left of the blue block')\n"
        "execute(movable, affordance_map=affordance_map)"]}
    said = {**dropped, "query": f"{DROPPED[10:-2]} while staying away from the green block"}
    return [*rows, dropped, said,
            {"lmp": "planner", "query": INSTRUCTION, "responses": list(planner)}]


class Backend(ReplayBackend):
    """The replay backend, keeping every request it answered."""

    def __init__(self, recordings: list[dict]) -> None:
        super().__init__(recordings)
        self.requests: list = []

    def complete(self, request):  # type: ignore[override]
        self.requests.append(request)
        return super().complete(request)


def runtime(backend: ReplayBackend, **config: object) -> LMPRuntime:
    return LMPRuntime(make_tabletop_scene(), backend, handler=RecordingHandler(),
                      config=LMPConfig(**config), transcript=Transcript())


def test_a_plan_that_drops_a_clause_is_sent_back_once_and_the_correction_runs() -> None:
    backend = Backend(entries(DROPPED, FULL))
    rt = runtime(backend)
    rt.run(INSTRUCTION)
    planner_calls = [r for r in backend.requests if r.prefix_id == "planner"]
    assert len(planner_calls) == 2
    correction = planner_calls[1].messages[-1].content
    assert correction.startswith(RETRY_PREFIX)
    assert "'green'" in correction and "avoidance clause" in correction
    (request,) = rt.handler.requests  # only the corrected plan executed
    assert "avoidance_map" in request.maps
    events = [e for e in rt.transcript.events if e["event"] == "checklist"]
    assert len(events) == 1 and events[0]["attempt"] == 1


def test_without_the_checklist_the_dropped_clause_runs() -> None:
    rt = runtime(Backend(entries(DROPPED, FULL)), clause_checklist=False, fold_avoided=False)
    rt.run(INSTRUCTION)
    assert [r.subtask for r in rt.handler.requests] == ["move to the left of the blue block"]


def test_a_dropped_avoidance_is_said_in_the_motion_without_asking() -> None:
    rt = runtime(Backend(entries(DROPPED, FULL)), clause_checklist=False)
    rt.run(INSTRUCTION)
    assert [r.subtask for r in rt.handler.requests] == [
        "move to the left of the blue block while staying away from the green block"]


def test_a_correction_that_is_worse_loses_to_the_first_plan() -> None:
    worse = "composer('move left')"
    rt = runtime(Backend(entries(DROPPED, worse)), fold_avoided=False)
    rt.run(INSTRUCTION)  # the first plan missed 'green' + avoidance; the second also 'blue'
    assert [r.subtask for r in rt.handler.requests] == ["move to the left of the blue block"]


def test_the_plans_post_conditions_are_evaluated_after_their_sub_task() -> None:
    plan = FULL + ("\nexpect(near('gripper', 'blue block', cm=12), "
                   "away('gripper', 'green block', cm=5))\nexpect(moved('blue block'))")
    rt = runtime(Backend(entries(plan)))
    rt.run(INSTRUCTION)
    results = rt.intent.results
    assert [r.condition for r in results] == [
        "near('gripper', 'blue block', cm=12)", "away('gripper', 'green block', cm=5)",
        "moved('blue block', cm=2.0)"]
    assert all(r.subtask == FULL[10:-2] for r in results)
    # the recording handler never moves anything: the gripper stays at rest, far from both
    # blocks, and the block stays where it was
    assert [r.held for r in results] == [False, True, False]
    assert rt.intent.verdict() is False
    assert [r.condition for r in rt.intent.failed()] == [
        "near('gripper', 'blue block', cm=12)", "moved('blue block', cm=2.0)"]
    logged = [e for e in rt.transcript.events if e["event"] == "intent"]
    assert [e["condition"] for e in logged] == [r.condition for r in results]


def test_exact_object_names_resolve_without_the_model() -> None:
    backend = Backend(entries(FULL))
    rt = runtime(backend)
    rt.run(INSTRUCTION)
    asked = {(r.prefix_id, r.messages[-1].content.split("# Query: ")[-1])
             for r in backend.requests}
    assert not any(lmp == "parse_query_obj" for lmp, _ in asked)
    resolved = {e["query"] for e in rt.transcript.events if e["event"] == "resolved"}
    assert {"blue block", "green block", "gripper"} <= resolved
    slow = runtime(Backend(entries(FULL)), resolve_exact_names=False)
    slow.run(INSTRUCTION)
    assert slow.llm_calls > rt.llm_calls


def test_a_post_condition_that_misses_a_constraint_is_sent_back_once() -> None:
    """The plan measures only the end state of "staying away": the runtime asks again, naming
    the missing away(...), and the corrected plan's conditions are the ones evaluated."""
    end_only = FULL + "\nexpect(near('gripper', 'blue block', cm=12))"
    measured = FULL + ("\nexpect(near('gripper', 'blue block', cm=12), "
                       "away('gripper', 'green block', cm=5))")
    backend = Backend(entries(end_only, measured))
    rt = runtime(backend)
    rt.run(INSTRUCTION)
    planner_calls = [r for r in backend.requests if r.prefix_id == "planner"]
    assert len(planner_calls) == 2
    correction = planner_calls[1].messages[-1].content
    assert correction.startswith(RETRY_PREFIX) and "away(" in correction
    assert [r.condition for r in rt.intent.results] == [
        "near('gripper', 'blue block', cm=12)", "away('gripper', 'green block', cm=5)"]
    off = runtime(Backend(entries(end_only, measured)), intent_checklist=False,
                  derived_conditions=False)
    off.run(INSTRUCTION)
    assert [r.condition for r in off.intent.results] == ["near('gripper', 'blue block', cm=12)"]


def test_an_object_found_by_description_can_be_named_so_in_a_condition() -> None:
    rt = runtime(Backend([{"lmp": "parse_query_obj", "query": "leftmost block",
                           "responses": ["ret_val = detect('pink block')"]}]))
    assert rt.query("parse_query_obj", "leftmost block").name == "pink block"
    assert rt.intent.namespace(lambda fn: fn)["near"]("leftmost block", "pink block", cm=1).held


def test_a_description_cut_short_by_a_map_program_is_made_whole() -> None:
    """The map program passes only "third block"; the runtime asks parse_query_obj for "third
    block from the right", as its own query says."""
    query = "a point above the third block from the right"
    rt = runtime(Backend([
        {"lmp": "get_affordance_map", "query": query, "responses": [
            "affordance_map = get_empty_affordance_map()\n"
            "block = parse_query_obj('third block')\n"
            "x, y, z = point_beside(block, 'top', 5)\naffordance_map[x, y, z] = 1\n"
            "ret_val = affordance_map"]},
        {"lmp": "parse_query_obj", "query": "third block from the right", "responses": [
            "blocks = [detect(n) for n in objects if n.endswith('block')]\n"
            "ret_val = sorted(blocks, key=lambda b: b.position[1], reverse=True)[2]"]}]))
    assert rt.query("get_affordance_map", query).sum() == 1
    (event,) = [e for e in rt.transcript.events if e["event"] == "description_completed"]
    assert event["whole"] == "third block from the right"
