"""Plans completed before they run: a final grasp is lifted, a lone drop is grasped first."""

from __future__ import annotations

import pytest

from tests.lmp.test_runtime_intent import Backend, runtime
from voxposer.lmp.plan_completion import (
    carry_stay_on,
    drop_final_reset,
    grasp_before_drop,
    hover_over,
    lift_after_grasp,
)

GRASP = ("composer('grasp the purple block while moving at 3x speed')\n"
         "expect(holding('purple block'), speed('gripper', 3))")


def test_a_final_grasp_of_a_block_is_lifted() -> None:
    assert lift_after_grasp(GRASP) == GRASP + "\ncomposer('back to default pose')"


@pytest.mark.parametrize("plan", [
    GRASP + "\ncomposer('back to default pose')",  # lifted already
    "composer('grasp the blue block')\ncomposer('move the blue block to the left side of the table')",
    "composer('grasp the top drawer handle')",  # a fixture's part: lifting would pull on it
    "composer('pick up the door handle')",
    "composer('move to the top of the blue block')",
    "for _ in range(2):\n    composer('grasp the blue block')",  # not a plain plan
    "",
])
def test_other_plans_are_left_alone(plan: str) -> None:
    assert lift_after_grasp(plan) is None


def _grasp_entries() -> list[dict]:
    return [
        {"lmp": "planner", "query": "pick up the blue block", "responses": [
            "composer('grasp the blue block')\nexpect(holding('blue block'))"]},
        {"lmp": "composer", "query": "grasp the blue block", "responses": [
            "movable = parse_query_obj('gripper')\n"
            "affordance_map = get_affordance_map('the blue block')\n"
            "execute(movable, affordance_map=affordance_map)"]},
        {"lmp": "composer", "query": "back to default pose", "responses": [
            "reset_to_default_pose()"]},
        {"lmp": "parse_query_obj", "query": "gripper", "responses": ["ret_val = detect('gripper')"]},
        {"lmp": "get_affordance_map", "query": "the blue block", "responses": [
            "affordance_map = get_empty_affordance_map()\n"
            "block = parse_query_obj('blue block')\n"
            "affordance_map[block.position] = 1\nret_val = affordance_map"]},
        {"lmp": "parse_query_obj", "query": "blue block", "responses": [
            "ret_val = detect('blue block')"]},
    ]


def test_the_runtime_lifts_after_a_final_grasp_and_says_so() -> None:
    rt = runtime(Backend(_grasp_entries()))
    rt.run("pick up the blue block")
    assert rt.handler.resets == 1, "the appended 'back to default pose' ran"
    (event,) = [e for e in rt.transcript.events if e["event"] == "plan_completed"]
    assert event["added"] == "composer('back to default pose')"
    off = runtime(Backend(_grasp_entries()), lift_after_grasp=False)
    off.run("pick up the blue block")
    assert off.handler.resets == 0


DROP_PLAN = ("composer('grasp the pink block')\ncomposer('back to default pose')\n"
             "composer('move the pink block to a point 9cm above the right side of the table')\n"
             "composer('release the pink block')")


@pytest.mark.parametrize("subtask", [
    "release the pink block over the right side of the table",
    "drop the pink block at the right side of the table",
    "put the pink block down on the right side of the table",
    "let the pink block fall onto the right side of the table",
])
def test_a_drop_of_an_object_never_grasped_becomes_grasp_lift_carry_release(subtask: str) -> None:
    plan = f"composer({subtask!r})\nexpect(on('pink block', 'table', 'right side'))"
    assert grasp_before_drop(plan) == DROP_PLAN + "\nexpect(on('pink block', 'table', 'right side'))"


@pytest.mark.parametrize("plan", [
    DROP_PLAN,  # grasped first: the examples' plan
    "composer('grab the pink block')\ncomposer('drop the pink block at the back side of the table')",
    "composer('release the top drawer handle')",  # no place
    "composer('put the top drawer handle on the back side of the table')",  # a fixture's part
    "composer('move to the back left corner of the table')",
    "composer('place the gripper at the top of the blue block')",  # the hand itself: a motion
    "composer('put your hand at the left of the pink block')",
    "composer('set the end effector over the back side of the table')",
    "for _ in range(2):\n    composer('drop the blue block on the table')",  # not a plain plan
])
def test_drops_after_a_grasp_and_other_plans_are_left_alone(plan: str) -> None:
    assert grasp_before_drop(plan) is None


def test_the_runtime_grasps_before_a_lone_drop_and_says_so() -> None:
    entries = [{"lmp": "planner", "query": "release the blue block over the table", "responses": [
        "composer('release the blue block over the table')"]}]
    rt = runtime(Backend(entries))
    with pytest.raises(Exception, match="grasp the blue block"):  # the replay has no composer
        rt.run("release the blue block over the table")
    grasp, derived = [e for e in rt.transcript.events if e["event"] == "plan_completed"]
    assert grasp["why"] == "a sub-task drops an object the plan never grasped"
    assert "released('blue block')" in derived["added"]  # the release then asks it


STAY_OBJECTS = ("table", "gripper", "yellow block", "brown block", "blue block")


@pytest.mark.parametrize(("instruction", "plan", "expected"), [
    # the clause dropped: the one motion carries it
    ("please move to the back side of the table, staying on the top of the yellow block",
     "composer('move to the back side of the table')\nexpect(on('gripper', 'table', 'back side'))",
     "composer('move to the back side of the table while staying on the top of the yellow "
     "block')\nexpect(on('gripper', 'table', 'back side'))"),
    # the clause planned as a destination after the motion: dropped, given to the motion
    ("take the gripper to the back left corner of the table but stay on the front side of the "
     "brown block",
     "composer('move to the back left corner of the table')\n"
     "composer('move to the front side of the brown block')\n"
     "expect(on('gripper', 'brown block', 'front side'))",
     "composer('move to the back left corner of the table while staying on the front side of "
     "the brown block')"),
    # a distance to keep planned as a visit to the object: dropped, the motion keeps it
    ("take the gripper to the right side of the table and keep 11cm clear of the blue block",
     "composer('move to the right side of the table')\n"
     "composer('move to a point 11cm above the blue block')\n"
     "expect(above('gripper', 'blue block', cm=11))\ncomposer('back to default pose')",
     "composer('move to the right side of the table while staying at least 11cm from the blue "
     "block')\ncomposer('back to default pose')"),
    # the motion said as reaching a place, the clause planned as a destination after it
    ("reach the right side of the table; your path should stay on the top of the blue block",
     "composer('reach the right side of the table')\n"
     "composer('move to the top of the blue block')",
     "composer('reach the right side of the table while staying on the top of the blue "
     "block')"),
    # the clause said as what the hand never leaves
    ("the gripper should end at the back left corner of the table, never leaving the front side "
     "of the brown block",
     "composer('move to the back left corner of the table')",
     "composer('move to the back left corner of the table while staying on the front side of "
     "the brown block')"),
    ("get to the back side of the table while staying 7 cm or more away from the blue block",
     "composer('move to the back side of the table')",
     "composer('move to the back side of the table while staying at least 7cm from the blue "
     "block')"),
    # dev records, extra dev phrasings (ad-hoc seeds 27, 28, 30): "don't leave", "keeping it
    # on", a motion said with "steer", a "go to the … of the table" before the clause, and a
    # hover above the object in place of the clause
    ("move over to the right side of the table and don't leave the top of the blue block",
     "composer('move to the right side of the table')\n"
     "composer('move to a point 10cm above the top of the blue block')",
     "composer('move to the right side of the table while staying on the top of the blue "
     "block')"),
    ("steer the hand to the right side of the table, keeping it on the left of the brown block",
     "composer('steer the hand to the right side of the table')",
     "composer('steer the hand to the right side of the table while staying on the left of the "
     "brown block')"),
    ("can you go to the back side of the table? stay on the front side of the yellow block as "
     "you do",
     "composer('move to the back side of the table')\n"
     "composer('move to the front side of the yellow block')",
     "composer('move to the back side of the table while staying on the front side of the "
     "yellow block')"),
    # dev records, a third set of extra dev phrasings (ad-hoc seed 309): the clause replaced by
    # a distance the instruction never says, and a post-condition keeping it
    ("get to the front right corner of the table without leaving the top of the blue block",
     "composer('move to the front right corner of the table while staying at least 10cm from "
     "the blue block')\nexpect(on('gripper', 'table', 'front right corner'), away('gripper', "
     "'blue block', cm=10))",
     "composer('move to the front right corner of the table while staying on the top of the "
     "blue block')\nexpect(on('gripper', 'table', 'front right corner'))"),
])
def test_a_dropped_staying_on_clause_is_given_to_the_motion(instruction: str, plan: str,
                                                            expected: str) -> None:
    assert carry_stay_on(instruction, plan, STAY_OBJECTS) == expected


@pytest.mark.parametrize(("instruction", "plan"), [
    ("move to the back side of the table while staying on the top of the blue block",
     "composer('move to the back side of the table while staying on the top of the blue block')"),
    ("move to the back side of the table while staying on the top of the blue block",  # 2 motions
     "composer('move to the left side of the table')\ncomposer('move to the back side of the "
     "table')"),
    ("push the blue block while it stays on the left side of the table",  # a table part
     "composer('push the blue block to the left')"),
    ("move to the back side of the table", "composer('move to the back side of the table')"),
    ("go to the back side of the table, keeping 9 cm from the blue block",  # carried already
     "composer('move to the back side of the table while staying at least 9cm from the blue "
     "block')"),
    # a distance the instruction says is kept (however its number is written), and the
    # clause then has no motion to go to
    ("go to the back side of the table 9cm from the blue block without leaving the top of the "
     "blue block",
     "composer('move to the back side of the table while staying at least 9cm from the blue "
     "block')"),
    ("go to the back side of the table 9.0cm from the blue block without leaving the top of "
     "the blue block",
     "composer('move to the back side of the table while staying at least 9cm from the blue "
     "block')"),
])
def test_plans_that_carry_the_clause_or_are_unclear_are_left_alone(instruction: str,
                                                                   plan: str) -> None:
    assert carry_stay_on(instruction, plan, STAY_OBJECTS) is None


MOVE = "composer('move to the right side of the table')\nexpect(on('gripper', 'table', 'right side'))"


def test_a_final_reset_after_a_hand_motion_is_dropped() -> None:
    assert drop_final_reset(MOVE + "\ncomposer('back to default pose')") == MOVE


@pytest.mark.parametrize("plan", [
    MOVE,
    "composer('grasp the blue block')\ncomposer('back to default pose')",  # the lift
    DROP_PLAN + "\ncomposer('back to default pose')",  # after the release
    "composer('push the blue block to the back side of the table')\n"
    "composer('back to default pose')",
    "composer('back to default pose')",
])
def test_other_final_resets_stay(plan: str) -> None:
    assert drop_final_reset(plan) is None


SCENE = ("table", "gripper", "blue block", "pink block", "brown block")


@pytest.mark.parametrize(("instruction", "subtask", "said"), [
    ("push the brown block to the back side of the table, then hover 10cm over it",
     "hover the brown block to a point 10cm above it", "move to a point 10cm above the brown block"),
    ("first hover 10cm over the blue block, then hover 12cm over the pink block",
     "hover the pink block 10cm above the table", "move to a point 12cm above the pink block"),
    ("hover over the blue block", "hover the blue block", "move to a point above the blue block"),
])
def test_a_sub_task_that_makes_the_object_hover_moves_the_hand(instruction: str, subtask: str,
                                                               said: str) -> None:
    plan = f"composer({subtask!r})\ncomposer('move to the right side of the table')"
    out = hover_over(instruction, plan, SCENE)
    assert out == f"composer({said!r})\ncomposer('move to the right side of the table')"


@pytest.mark.parametrize(("instruction", "plan"), [
    # the hand hovers already
    ("hover 10cm over the blue block", "composer('hover 10cm over the blue block')"),
    # the instruction hovers over nothing: "hover the blue block" may be a held block's motion
    ("lift the blue block and hover it over the table", "composer('hover the blue block')"),
])
def test_hovers_of_the_hand_or_not_asked_are_left_alone(instruction: str, plan: str) -> None:
    assert hover_over(instruction, plan, SCENE) is None


def test_the_runtime_moves_the_hand_for_a_hover_and_says_so() -> None:
    instruction = "hover 10cm over the blue block"
    entries = [{"lmp": "planner", "query": instruction, "responses": [
        "composer('hover the blue block 10cm above the table')"]}]
    rt = runtime(Backend(entries))
    with pytest.raises(Exception, match="move to a point 10cm above the blue block"):
        rt.run(instruction)  # the replay has no composer: the sub-task it was asked names it
    hover = next(e for e in rt.transcript.events if e["event"] == "plan_completed")
    assert hover["why"] == "a sub-task made the object hover"
