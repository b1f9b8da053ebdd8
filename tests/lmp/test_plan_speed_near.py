"""A speed near an object planned as a sub-task of its own is folded into the hand's motion."""

from __future__ import annotations

import pytest

from voxposer.lmp.plan_pipeline import complete_plan
from voxposer.lmp.plan_speed_near import speed_near_folded
from voxposer.lmp.registry import LMPConfig

NAMES = ("table", "robot", "gripper", "green block", "pink block", "blue line")
SAID = ("reach the back left corner of the table; when the pink block is less than 5cm away, "
        "move at faster speed")
MOTION = ("composer('move to the back left corner of the table')\n"
          "expect(on('gripper', 'table', 'back left corner'))\n")


@pytest.mark.parametrize("alone", [
    # dev records, a third set of extra dev phrasings (ad-hoc seed 305): the speed as code
    """composer('speed(gripper, 2, away="pink block", cm=5)')\n"""
    "expect(speed('gripper', 2), away('pink block', 'table', cm=5))",
    # the speed as a constraint alone, in words
    "composer('move at faster speed whenever you are within 5cm of the pink block')",
])
def test_the_speed_alone_becomes_the_speed_of_the_motion(alone: str) -> None:
    assert speed_near_folded(SAID, MOTION + alone, NAMES) == (
        "composer('move to the back left corner of the table while moving at faster speed when "
        "within 5cm from the pink block')\nexpect(on('gripper', 'table', 'back left corner'))")


def test_the_instructions_own_speed_words_are_kept() -> None:
    said = ("go to the back side of the table, at a quarter of the speed within 9 cm of the pink "
            "block")
    out = speed_near_folded(said, "composer('move to the back side of the table')\n"
                            "composer('go slowly near the pink block')", NAMES)
    assert out == ("composer('move to the back side of the table while moving at a quarter of "
                   "the speed when within 9cm from the pink block')")


@pytest.mark.parametrize(("instruction", "code"), [
    # already said in the motion
    (SAID, "composer('move to the back left corner of the table while moving at faster speed "
           "when within 5cm from the pink block')"),
    # no speed in the instruction
    ("reach the back left corner of the table, keeping 5cm from the pink block",
     MOTION + "composer('keep at least 5cm away from the pink block')"),
    # two objects: which one the zone is around is not known
    ("reach the back left corner of the table; within 5cm of the pink block or the green block "
     "move at faster speed", MOTION + "composer('move at faster speed near the blocks')"),
    # two motions: which one the speed belongs to is not known
    (SAID, MOTION + "composer('move to the front side of the table')\n"
                    "composer('move at faster speed within 5cm of the pink block')"),
    # the other sub-task is a motion of its own, not a speed alone
    (SAID, MOTION + "composer('grasp the pink block')"),
])
def test_plans_without_a_speed_alone_are_left(instruction: str, code: str) -> None:
    assert speed_near_folded(instruction, code, NAMES) is None


def test_the_pipeline_folds_the_speed_and_asks_it_near_the_object() -> None:
    code = MOTION + """composer('speed(gripper, 2, away="pink block", cm=5)')"""
    events: list[dict[str, str]] = []
    out = complete_plan(SAID, code, LMPConfig(), NAMES, lambda **e: events.append(e))
    assert out.splitlines()[1] == ("expect(on('gripper', 'table', 'back left corner'), "
                                   "speed('gripper', 2, near='pink block', cm=5))")
    assert events[0]["why"] == "a sub-task said the speed with no motion of its own"
    off = complete_plan(SAID, code, LMPConfig(speed_near_folded=False), NAMES, lambda **e: None)
    assert "speed(gripper, 2" in off
