"""The plan review: both checklists send a plan back once, and the better plan runs."""

from __future__ import annotations

from voxposer.lmp.plan_review import POST_CONDITION, PlanReview, graft_conditions
from voxposer.lmp.unasked import UNASKED_GRASP

STAY = "move to the back side of the table while staying on the top of the yellow block"


def test_the_review_sends_a_plan_back_once_and_keeps_the_better_one() -> None:
    end_state = f"composer({STAY!r})\nexpect(on('gripper', 'yellow block', 'top'))"
    review = PlanReview(STAY, max_attempts=3)
    code, message, gaps = review.review(end_state, attempt=1)
    assert message is not None and "passed_on" in message and len(gaps) == 2
    worse = (end_state + "\ncomposer('move to the front side of the table while staying on "
             "the top of the yellow block')\nexpect(on('gripper', 'table', 'front side'))")
    code, message, _ = review.review(worse, attempt=2)  # no better once grafted: the first runs
    assert message is None and code == end_state
    off = PlanReview(STAY, max_attempts=3, post_conditions=False)
    assert off.review(end_state, attempt=1)[1] is None


def test_a_correction_of_post_conditions_keeps_the_first_plans_sub_tasks() -> None:
    """Asked only for post-conditions, the model also appended "back to default pose" (which
    would undo a motion the task judges at its end): the first plan's sub-tasks run, with the
    correction's conditions."""
    end_state = f"composer({STAY!r})\nexpect(on('gripper', 'yellow block', 'top'))"
    replanned = (f"composer({STAY!r})\nexpect(on('gripper', 'table', 'back side'), "
                 "passed_on('gripper', 'yellow block', 'top'))\ncomposer('back to default pose')")
    review = PlanReview(STAY, max_attempts=3)
    review.review(end_state, attempt=1)
    code, message, gaps = review.review(replanned, attempt=2)
    assert message is None and gaps == []
    assert code == (f"composer({STAY!r})\nexpect(on('gripper', 'table', 'back side'), "
                    "passed_on('gripper', 'yellow block', 'top'))")


def test_grafting_needs_plain_plans_and_matches_sub_tasks_by_their_words() -> None:
    plan = ("composer('grasp the blue block')\nexpect(holding('blue block'))\n"
            "composer('move the blue block to the left side of the table')")
    correction = ("composer('move the blue block to the left side of the table')\n"
                  "expect(on('blue block', 'table', 'left side'))")
    assert graft_conditions(plan, correction) == (
        "composer('grasp the blue block')\nexpect(holding('blue block'))\n"
        "composer('move the blue block to the left side of the table')\n"
        "expect(on('blue block', 'table', 'left side'))")
    looped = "for s in ['a', 'b']:\n    composer(s)"
    assert graft_conditions(looped, correction) is None
    assert graft_conditions(plan, "x = 1\n" + correction) is None


def test_clause_and_post_condition_gaps_are_named_in_one_correction() -> None:
    instruction = "push the green block to the back side of the table slowly while staying " \
                  "away from the red block"
    plan = ("composer('push the green block to the back side of the table slowly')\n"
            "expect(on('green block', 'table', 'back side'))")
    _, message, gaps = PlanReview(instruction, max_attempts=3).review(plan, attempt=1)
    assert sorted(g.kind for g in gaps) == ["avoidance clause", "colour", "post-condition"]
    assert message is not None
    assert "'red'" in message and "speed('gripper', <scale>)" in message
    only_clauses = PlanReview(instruction, max_attempts=3, post_conditions=False)
    assert [g.kind for g in only_clauses.gaps(plan) or []] == ["colour", "avoidance clause"]


def test_a_correction_that_drops_the_plan_for_one_post_condition_is_not_run() -> None:
    """Asked about one sub-task, a small model answers with it alone: the plan with fewer clause
    gaps runs, although both have as many gaps in all."""
    instruction = "push the yellow block to the right side of the table"
    review = PlanReview(instruction, max_attempts=3, clauses=True, post_conditions=True)
    plan = ("composer('grasp the yellow block')\nexpect(holding('yellow block'))\n"
            "composer('push the yellow block to the right side of the table')\n"
            "expect(away('gripper', 'yellow block'))")
    _, correction, gaps = review.review(plan, attempt=1)
    assert {g.kind for g in gaps} == {UNASKED_GRASP, POST_CONDITION}
    assert correction is not None and "asks no grasp" in correction
    fragment = "composer('push the block to the left side of the table')\nexpect(moved('block'))"
    code, correction, gaps = review.review(fragment, attempt=2)
    assert len(gaps) == 2 and correction is None and code == plan
