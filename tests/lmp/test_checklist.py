"""The clause checklist: a plan that drops a clause of the instruction is caught."""

from __future__ import annotations

import pytest

from tests.lmp.reference_plans import reference_plans
from voxposer.bench.tasks import TASKS
from voxposer.lmp.checklist import (
    checklist_message,
    clause_gaps,
    constraint_only,
    planned_subtasks,
)


def test_planned_subtasks_reads_composer_calls_without_running_them() -> None:
    code = ("composer('grasp the blue block')\nexpect(holding('blue block'))\n"
            "for s in ['a', 'b']:\n    composer(f'move {s} to the red line')")
    assert planned_subtasks(code) == ["grasp the blue block", "move  to the red line"]
    assert planned_subtasks("composer('x'") is None


def test_a_dropped_avoidance_clause_is_named() -> None:
    gaps = clause_gaps("move the end effector right above the cyan block, and please avoid the "
                       "red one", ["move to a point above the cyan block"])
    assert {(g.kind, g.words) for g in gaps} == {("colour", "red"),
                                                 ("avoidance clause", "avoid")}
    message = checklist_message("…", gaps)
    assert "'red'" in message and "'avoid'" in message


def test_dropped_speeds_and_distances_are_named() -> None:
    gaps = clause_gaps("go to the back left corner and keep at least 9cm away from the green "
                       "block, slowly", ["move to the back left corner of the table"])
    assert {g.kind for g in gaps} == {"colour", "number", "avoidance clause", "speed clause"}
    covered = clause_gaps("go to the back left corner and keep at least 9cm away from the green "
                          "block, slowly", ["move to the back left corner of the table while "
                                            "staying 9cm away from the green block at slower "
                                            "speed"])
    assert covered == []


def test_a_constraint_split_off_its_motion_is_caught() -> None:
    plan = ["go to the back left corner of the table",
            "move at faster speed whenever you are within 3cm of the green block"]
    gaps = clause_gaps("go to the back left corner of the table and move at faster speed "
                       "whenever you are within 3cm of the green block", plan)
    assert [g.kind for g in gaps] == ["constraint without a motion"]
    assert "only state a constraint" in checklist_message("…", gaps)
    for motion in ("move to the left of the blue block while staying away from the green block",
                   "grasp the yellow block while moving at a quarter of the speed",
                   "move slowly to the cabinet", "back to default pose"):
        assert not constraint_only(motion), motion


@pytest.mark.parametrize("task", sorted(TASKS))
def test_reference_plans_of_every_task_have_no_gaps(task: str) -> None:
    """The checklist never sends a correct plan of a benchmark template back."""
    for instruction, code in reference_plans(task):
        assert clause_gaps(instruction, planned_subtasks(code) or []) == [], instruction


def test_one_pattern_tells_the_hands_motions_from_other_sub_tasks() -> None:
    import re

    from voxposer.lmp.checklist import HAND_MOTION_START

    motion = re.compile(HAND_MOTION_START, re.I)
    for said in ("move to the back side of the table", "then go to the left of the red block",
                 "steer the hand to the right side", "make your way to the front side",
                 "bring the gripper to the top of the blue block", "take your hand to the corner",
                 "reach the back left corner", "first navigate to the right side"):
        assert motion.match(said), said
    for said in ("push the blue block to the back", "grasp the red block",
                 "bring the blue block to the corner", "open the top drawer", "movement"):
        assert not motion.match(said), said


def test_a_speed_zone_is_read_over_in_or_above_a_table_part() -> None:
    from voxposer.lmp.checklist import REGION_SAID

    for said, part in (("with faster speed above the right side of the table", "right side"),
                       ("go slowly over the back left corner of the table", "back left corner"),
                       ("at 3x speed in the left half of the table", "left half")):
        found = REGION_SAID.search(said)
        assert found is not None and found.group(1) == part, said
    assert REGION_SAID.search("go to the right side of the table") is None  # a place, not a zone
