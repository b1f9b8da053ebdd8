"""A constraint stated only in a post-condition is carried into the motion's words."""

from __future__ import annotations

from voxposer.lmp.plan_carry import carry_stated_constraints
from voxposer.lmp.plan_pipeline import complete_plan
from voxposer.lmp.registry import LMPConfig

OBJECTS = ("table", "robot", "gripper", "green block", "blue block", "red block")


def test_a_distance_kept_only_in_the_post_condition_reaches_the_motion() -> None:
    code = ("composer('move to the back side of the table')\n"
            "expect(on('gripper', 'table', 'back side'), away('gripper', 'green block', cm=9))")
    out = carry_stated_constraints("reach the back side of the table, never nearer than 9 cm "
                                   "to the green block", code, OBJECTS)
    assert out is not None
    new, changed = out
    assert new.splitlines()[0] == ("composer('move to the back side of the table while staying "
                                   "at least 9cm from the green block')")
    assert new.splitlines()[1] == code.splitlines()[1]  # the condition stays
    assert changed == [new.splitlines()[0][10:-2]]


def test_an_away_without_a_distance_asks_to_stay_away() -> None:
    code = "composer('go to the front side of the table')\nexpect(away('gripper', 'red block'))"
    new, _ = carry_stated_constraints("x", code, OBJECTS) or ("", [])
    assert "while staying away from the red block" in new


def test_a_scoped_speed_gets_the_instructions_own_phrase_or_the_examples_words() -> None:
    code = ("composer('move to the back left corner of the table')\n"
            "expect(speed('gripper', 0.25, near='green block', cm=7))")
    said = "head for the back left corner, at a quarter of the speed within 7cm of the green block"
    new, _ = carry_stated_constraints(said, code, OBJECTS) or ("", [])
    assert new.splitlines()[0] == ("composer('move to the back left corner of the table at a "
                                   "quarter of the speed when within 7cm of the green block')")
    fast = code.replace("0.25", "2")
    new, _ = carry_stated_constraints("hurry near the green block", fast, OBJECTS) or ("", [])
    assert "at faster speed when within 7cm of the green block" in new
    region = ("composer('go to the right side of the table')\n"
              "expect(speed('gripper', 0.5, inside='back side'))")
    new, _ = carry_stated_constraints("x", region, OBJECTS) or ("", [])
    assert "at half of the speed in the back side of the table" in new


def test_an_unscoped_speed_takes_the_instructions_zone() -> None:
    code = ("composer('move to the front right corner of the table')\n"
            "expect(speed('gripper', 2))")
    said = "travel to the front right corner; in the right side of the table, go at faster speed"
    new, _ = carry_stated_constraints(said, code, OBJECTS) or ("", [])
    assert new.splitlines()[0] == ("composer('move to the front right corner of the table at "
                                   "faster speed in the right side of the table')")
    near = "reach the back side, a quarter of the speed within 5cm of the red block"
    new, _ = carry_stated_constraints(near, code.replace("2)", "0.25)"), OBJECTS) or ("", [])
    assert "at a quarter of the speed when within 5cm of the red block" in new
    new, _ = carry_stated_constraints("go slowly", code.replace("2)", "0.5)"), OBJECTS) or ("", [])
    assert new.splitlines()[0].endswith("of the table at half of the speed')")


def test_a_push_gets_the_examples_avoiding_words_for_its_block_or_the_gripper() -> None:
    for what in ("yellow block", "gripper"):
        code = ("composer('push the yellow block to the front right corner of the table')\n"
                f"expect(away({what!r}, 'green block', cm=10))")
        new, _ = carry_stated_constraints("x", code, (*OBJECTS, "yellow block")) or ("", [])
        assert new.splitlines()[0] == ("composer('push the yellow block to the front right "
                                       "corner of the table while staying away from the green "
                                       "block')")


def test_plans_whose_words_already_carry_it_or_that_move_an_object_are_left() -> None:
    carried = ("composer('move to the back side of the table while staying at least 9cm from "
               "the green block')\nexpect(away('gripper', 'green block', cm=9))")
    push = ("composer('push the blue block to the back while avoiding the green block')\n"
            "expect(away('blue block', 'green block'))")
    other = "composer('push the blue block to the back')\nexpect(away('red block', 'green block'))"
    toward = "composer('move to the top of the green block')\nexpect(away('gripper', 'green block'))"
    spoken = ("composer('move to the back side of the table slowly')\n"
              "expect(speed('gripper', 0.5, near='green block', cm=5))")
    loop = "for i in range(2):\n    composer('move left')\nexpect(away('gripper', 'red block'))"
    for code in (carried, push, other, toward, spoken, loop):
        assert carry_stated_constraints("x", code, OBJECTS) is None, code


def test_the_pipeline_carries_it_then_derives_no_second_condition() -> None:
    code = ("composer('move to the back side of the table')\n"
            "expect(away('gripper', 'green block', cm=9))")
    events: list[dict] = []
    out = complete_plan("reach the back side, never nearer than 9 cm to the green block", code,
                        LMPConfig(), OBJECTS, lambda **e: events.append(e))
    assert out.startswith("composer('move to the back side of the table while staying at "
                          "least 9cm from the green block')")
    assert out.count("away(") == 1
    assert events[0]["why"].startswith("a post-condition kept a distance")
    off = complete_plan("x", code, LMPConfig(carry_stated_constraints=False,
                                             derived_conditions=False), OBJECTS, lambda **e: None)
    assert off == code


def test_a_motion_said_with_another_verb_gets_the_speed_of_its_post_condition() -> None:
    """Dev record (ad-hoc seed 28, an extra dev phrasing): "steer the hand to …, with faster
    speed above the right side of the table" planned as a motion without the speed and a
    ``speed(…, inside=…)`` post-condition."""
    said = ("steer the hand to the front right corner of the table, with faster speed above the "
            "right side of the table")
    code = ("composer('steer the hand to the front right corner of the table')\n"
            "expect(speed('gripper', 2, inside='right side'))")
    new, _ = carry_stated_constraints(said, code, OBJECTS) or ("", [])
    assert new.splitlines()[0] == ("composer('steer the hand to the front right corner of the "
                                   "table at faster speed in the right side of the table')")
    carried = "composer('bring the blue block to the back side of the table')\n" \
              "expect(away('gripper', 'red block'))"
    assert carry_stated_constraints("x", carried, OBJECTS) is None  # the block, not the hand
