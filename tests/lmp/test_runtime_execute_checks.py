"""An ``execute`` whose entity is already at its target is sent back before anything runs."""

from __future__ import annotations

import pytest

from voxposer.errors import ResultError
from voxposer.lmp import LMPRuntime, RecordingHandler, Transcript, make_tabletop_scene
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.backends.replay import ReplayBackend
from voxposer.lmp.checks import check_execute_target, corrected_movable

CENTRE = "a point at the center of the pink block"
BLOCK_AS_MOVABLE = ("movable = parse_query_obj('pink block')\n"
                    f"affordance_map = get_affordance_map('{CENTRE}')\n"
                    "execute(movable, affordance_map=affordance_map)")
GRIPPER_AS_MOVABLE = ("movable = parse_query_obj('gripper')\n"
                      f"affordance_map = get_affordance_map('{CENTRE}')\n"
                      "gripper_map = get_gripper_map('close everywhere')\n"
                      "execute(movable, affordance_map=affordance_map, gripper_map=gripper_map)")
ENTRIES = [
    {"lmp": "planner", "query": "pick up the pink block",
     "responses": ["composer('grasp the pink block')"]},
    {"lmp": "composer", "query": "grasp the pink block",
     "responses": [BLOCK_AS_MOVABLE, GRIPPER_AS_MOVABLE]},
    {"lmp": "get_affordance_map", "query": CENTRE, "responses": [
        "affordance_map = get_empty_affordance_map()\n"
        "x, y, z = point_on(parse_query_obj('pink block'), 'center')\n"
        "affordance_map[x, y, z] = 1\nret_val = affordance_map"]},
    {"lmp": "get_gripper_map", "query": "close everywhere", "responses": [
        "gripper_map = get_empty_gripper_map()\ngripper_map[:] = CLOSED\nret_val = gripper_map"]},
    # the plan ends on the grasp, so the runtime appends the lift (plan_completion)
    {"lmp": "composer", "query": "back to default pose", "responses": ["reset_to_default_pose()"]},
]


def test_the_block_as_its_own_movable_is_corrected_before_it_executes() -> None:
    rt = LMPRuntime(make_tabletop_scene(), ReplayBackend(ENTRIES), handler=RecordingHandler(),
                    transcript=Transcript())
    rt.run("pick up the pink block")
    (request,) = rt.handler.requests  # only the corrected program reached the robot
    assert request.movable()["name"] == "gripper"
    failed = [e for e in rt.transcript.events if e["event"] == "exec" and not e["ok"]]
    assert len(failed) == 1 and "inside the pink block itself" in failed[0]["error"]


def test_a_push_or_a_gripper_move_passes() -> None:
    api = LMPAPI(make_tabletop_scene())
    pink, table = api.detect("pink block"), api.detect("table")
    here = api.maps.get_empty_affordance_map()
    here[tuple(pink.position)] = 1
    there = api.maps.get_empty_affordance_map()
    there[tuple(api.point_on(table, "back left corner"))] = 1
    check_execute_target(pink, there)  # push it somewhere else
    check_execute_target(api.detect("gripper"), here)  # the gripper goes to the block
    check_execute_target(pink, None)
    with pytest.raises(ResultError, match="nothing would move"):
        check_execute_target(pink, here)


def test_an_execute_without_a_target_is_corrected_before_it_executes() -> None:
    entries = [dict(e) for e in ENTRIES]
    entries[1] = {"lmp": "composer", "query": "grasp the pink block", "responses": [
        "movable = parse_query_obj('gripper')\nexecute(movable)", GRIPPER_AS_MOVABLE]}
    rt = LMPRuntime(make_tabletop_scene(), ReplayBackend(entries), handler=RecordingHandler(),
                    transcript=Transcript())
    rt.run("pick up the pink block")
    (request,) = rt.handler.requests
    assert "affordance_map" in request.maps
    failed = [e for e in rt.transcript.events if e["event"] == "exec" and not e["ok"]]
    assert len(failed) == 1 and "needs an affordance_map" in failed[0]["error"]


BESIDE = "the front side of the pink block"


def _beside(composer: list[str]) -> list[dict]:
    return [
        {"lmp": "planner", "query": "go to the front side of the pink block",
         "responses": [f"composer('move to {BESIDE}')"]},
        {"lmp": "composer", "query": f"move to {BESIDE}", "responses": composer},
        {"lmp": "get_affordance_map", "query": BESIDE, "responses": [
            "affordance_map = get_empty_affordance_map()\n"
            "x, y, z = point_beside(parse_query_obj('pink block'), 'front', 5)\n"
            "affordance_map[x, y, z] = 1\nret_val = affordance_map"]},
    ]


def test_a_hand_motion_with_the_object_as_movable_is_corrected_before_it_executes() -> None:
    """'move to the front side of the pink block' written with the pink block as the movable
    would push the block in front of itself; the runtime moves the gripper instead, says so,
    and asks the model nothing more."""
    moved_block = f"movable = parse_query_obj('pink block')\naffordance_map = " \
                  f"get_affordance_map('{BESIDE}')\nexecute(movable, affordance_map=affordance_map)"
    backend = ReplayBackend(_beside([moved_block]))
    rt = LMPRuntime(make_tabletop_scene(), backend, handler=RecordingHandler(),
                    transcript=Transcript())
    rt.run("go to the front side of the pink block")
    (request,) = rt.handler.requests
    assert request.movable()["name"] == "gripper"
    (event,) = [e for e in rt.transcript.events if e["event"] == "movable_corrected"]
    assert event["movable"] == "pink block" and event["to"] == "gripper"
    assert not [e for e in rt.transcript.events if e["event"] == "exec" and not e["ok"]]


@pytest.mark.parametrize(("subtask", "movable", "corrected"), [
    ("move to the front side of the pink block", "pink block", "gripper"),
    ("move to the front side of the pink block", "gripper", None),
    ("nudge the pink block a few centimeters to the back", "gripper", "pink block"),
    ("push the pink block all the way to the back side of the table", "gripper", "pink block"),
    ("push the pink block to the back side of the table", "pink block", None),
    ("move the pink block to a point 9cm above the table", "gripper", None),  # carried
    ("close the top drawer by pushing", "gripper", None),
    ("push the top drawer closed", "gripper", None),  # a fixture: pushed through the hand
    ("push it to the left", "gripper", None),  # no object named
    ("hover the pink block to a point 10cm above it", "pink block", "gripper"),
    ("move away from the pink block", "pink block", "gripper"),
    ("move away from the pink block", "gripper", None),
])
def test_the_movable_is_what_the_sub_task_moves(subtask: str, movable: str,
                                                corrected: str | None) -> None:
    scene = make_tabletop_scene()
    entity = LMPAPI(scene).detect(movable)
    fix = corrected_movable(subtask, entity, scene.object_names)
    assert (fix[0] if fix else None) == corrected


@pytest.mark.parametrize(("query", "written", "expected"), [
    ("faster speed within 5cm of the yellow block", 0.5, 2.0),  # turned round: the words'
    ("a quarter of the speed in the right side of the table", 2.0, 0.25),
    ("faster speed within 5cm of the yellow block", 1.5, 1.5),  # agrees: kept
    ("within 5cm of the yellow block", 0.5, 0.5),  # no speed said: kept
])
def test_a_velocity_map_that_turns_the_words_round_is_corrected(query: str, written: float,
                                                                 expected: float) -> None:
    code = ("velocity_map = get_empty_velocity_map()\n"
            "block = parse_query_obj('yellow block')\n"
            f"set_voxel_by_radius(velocity_map, block.position, 13, {written})\n"
            "ret_val = velocity_map")
    rt = LMPRuntime(make_tabletop_scene(), ReplayBackend([
        {"lmp": "get_velocity_map", "query": query, "responses": [code]}]),
        handler=RecordingHandler(), transcript=Transcript())
    velocity = rt.query("get_velocity_map", query)
    assert set(velocity[velocity != 1.0].tolist()) == {expected}
    events = [e for e in rt.transcript.events if e["event"] == "speed_corrected"]
    assert len(events) == (expected != written)
