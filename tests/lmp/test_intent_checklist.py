"""The post-condition checklist: a constraint no post-condition measures is caught."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.lmp.reference_plans import reference_plans
from voxposer.bench.tasks import TASKS
from voxposer.lmp.intent_checklist import intent_gaps, intent_message, subtask_conditions

PROMPT = Path(__file__).parents[2] / "src" / "voxposer" / "lmp" / "prompts" / "planner.txt"
STAY = "move to the back side of the table while staying on the top of the yellow block"


def test_conditions_are_read_per_sub_task_in_order() -> None:
    code = ("composer('grasp the blue block')\nexpect(holding('blue block'))\n"
            "composer('move the blue block to the red line')\n"
            "expect(near('blue block', 'red line', cm=4), moved('blue block', toward='left'))")
    planned = subtask_conditions(code)
    assert planned is not None
    assert [s for s, _ in planned] == ["grasp the blue block",
                                       "move the blue block to the red line"]
    assert [(c.helper, c.subject, c.other) for c in planned[1][1]] == [
        ("near", "blue block", "red line"), ("moved", "blue block", "")]
    assert "toward" in planned[1][1][1].keywords
    assert subtask_conditions("composer('x'") is None


def test_staying_on_stated_as_an_end_state_is_caught() -> None:
    end_state = f"composer({STAY!r})\nexpect(on('gripper', 'yellow block', 'top'))"
    missing, wrong = intent_gaps(end_state)
    assert missing.kind == "post-condition" and "passed_on" in missing.words
    assert STAY in missing.words
    assert "replace it by passed_on('gripper', 'yellow block'" in wrong.words
    both = (f"composer({STAY!r})\nexpect(on('gripper', 'yellow block', 'top'), "
            "passed_on('gripper', 'yellow block', 'top'))")
    (gap,) = intent_gaps(both)  # the end state beside the block is still wrong
    assert "replace it" in gap.words
    path = (f"composer({STAY!r})\nexpect(on('gripper', 'table', 'back side'), "
            "passed_on('gripper', 'yellow block', 'top'))")
    assert intent_gaps(path) == []


def test_a_speed_without_its_zone_is_caught() -> None:
    region = "move to the front left corner of the table while moving at 3x speed in the left " \
             "side of the table"
    (gap,) = intent_gaps(f"composer({region!r})\nexpect(speed('gripper', 3))")
    assert "inside=" in gap.words
    assert intent_gaps(f"composer({region!r})\nexpect(speed('gripper', 3, inside='left side'))"
                       ) == []
    near = "move to the back side of the table while moving at faster speed when within 9cm " \
           "of the yellow block"
    (gap,) = intent_gaps(f"composer({near!r})\nexpect(on('gripper', 'table', 'back side'), "
                         "speed('gripper', 2))")
    assert "near=" in gap.words
    (gap,) = intent_gaps(f"composer({near!r})\nexpect(on('gripper', 'table', 'back side'))")
    assert "its speed" in gap.words


def test_a_push_judged_on_the_gripper_is_caught() -> None:
    push = "push the green block to the front right corner of the table while staying away " \
           "from the yellow block"
    gaps = intent_gaps(f"composer({push!r})\nexpect(on('gripper', 'table', 'front right "
                       "corner'), away('gripper', 'yellow block', cm=5))")
    assert len(gaps) == 2
    assert all("pushed object" in g.words for g in gaps)
    assert "'green ...'" in intent_message(gaps)
    assert intent_gaps(f"composer({push!r})\nexpect(on('green block', 'table', 'front right "
                       "corner'), away('green block', 'yellow block'))") == []


def test_where_a_push_ends_may_be_stated_after_a_later_sub_task() -> None:
    code = ("composer('push the blue block to the near end of the green line')\n"
            "composer('push the blue block to the far end of the green line')\n"
            "expect(moved('blue block', cm=10), near('blue block', 'green line', cm=4))")
    assert intent_gaps(code) == []


def test_plans_without_post_conditions_or_constraints_are_left_alone() -> None:
    assert intent_gaps(f"composer({STAY!r})") == []  # none stated: nothing to measure
    assert intent_gaps("composer('grasp the blue block')\nexpect(holding('blue block'))\n"
                       "composer('back to default pose')") == []


def test_the_planner_prompts_examples_have_no_gaps() -> None:
    """The examples the model imitates state every constraint they carry."""
    text = PROMPT.read_text()
    answers = [p.split("\n", 1)[1] for p in re.split(r"^### ", text, flags=re.M)
               if p.startswith("assistant")]
    assert len(answers) > 15
    for code in answers:
        assert intent_gaps(code) == [], code


@pytest.mark.parametrize("task", sorted(TASKS))
def test_reference_plans_of_every_task_have_no_post_condition_gaps(task: str) -> None:
    for instruction, code in reference_plans(task):
        assert intent_gaps(code) == [], instruction


def test_staying_on_a_part_of_the_table_asks_for_no_side_passed() -> None:
    """"… while staying on the right side of the table" keeps a push in a table part (``on``),
    it passes no object's side: asking for passed_on made the model measure the pushed block's
    side (dev seeds)."""
    plan = ("composer('push the yellow block to the right side of the table while staying on "
            "the right side of the table')\nexpect(on('yellow block', 'table', 'right side'))")
    assert intent_gaps(plan) == []


def test_moving_away_asks_for_no_distance_kept_on_the_way() -> None:
    """"move away from the X" starts beside X: "away" is where the hand goes (``far``), not a
    distance its path keeps, so no away(...) is asked for."""
    plan = ("composer('push the pink block to the back side of the table')\n"
            "expect(moved('pink block'))\ncomposer('move away from the pink block')\n"
            "expect(far('gripper', 'pink block'))")
    assert intent_gaps(plan) == []
    kept = plan.replace("move away from the pink block",
                        "move to the left side of the table while staying away from the pink block")
    assert len(intent_gaps(kept)) == 1  # a path clause: its distance is asked for
