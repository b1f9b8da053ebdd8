"""What a plan does that its instruction never asks is named or mended; correct plans are left
alone."""

from __future__ import annotations

import pytest

from tests.lmp.reference_plans import reference_plans
from voxposer.bench.intent_reference import with_expectation
from voxposer.bench.multistep import ENTRIES
from voxposer.bench.paraphrases import paraphrase
from voxposer.bench.task import episode_rng
from voxposer.bench.tasks import TASKS
from voxposer.lmp.checklist import planned_subtasks
from voxposer.lmp.plan_avoid import fold_avoided
from voxposer.lmp.plan_places import named_places_only
from voxposer.lmp.plan_review import PlanReview
from voxposer.lmp.unasked import (
    UNASKED_GRASP,
    UNNAMED_PLACE,
    avoided_objects,
    to_avoided,
    unasked_gaps,
)

PUSH_AWAY = ("push the green block to the front right corner of the table and keep it away "
             "from the yellow block")


def _gaps(instruction: str, code: str) -> set[tuple[str, str]]:
    return {(g.kind, g.words) for g in unasked_gaps(instruction, planned_subtasks(code) or [])}


def test_a_grasp_and_carry_for_a_push_is_named() -> None:
    code = ("composer('grasp the green block')\ncomposer('move the green block to the front "
            "right corner of the table')\ncomposer('release the green block')")
    assert _gaps(PUSH_AWAY, code) == {(UNASKED_GRASP, "grasp the green block"),
                                      (UNASKED_GRASP, "release the green block")}
    assert _gaps("pick up the green block and put it on the front right corner of the table",
                 code) == set()


def test_a_motion_around_the_object_to_avoid_is_mended_into_the_push() -> None:
    instruction = ("push the yellow block to the right side of the table and go around the "
                   "pink block")
    assert avoided_objects(instruction) == {"pink block"}
    assert to_avoided("move around the pink block", "pink block")
    assert not to_avoided("move away from the pink block", "pink block")
    code = ("composer('push the yellow block to the right side of the table')\n"
            "expect(on('yellow block', 'table', 'right side'))\n"
            "composer('move around the pink block')\n"
            "expect(away('gripper', 'pink block', cm=10))\n"
            "composer('back to default pose')")
    assert fold_avoided(instruction, code) == (
        "composer('push the yellow block to the right side of the table while staying away "
        "from the pink block')\nexpect(on('yellow block', 'table', 'right side'))\n"
        "composer('back to default pose')")
    kept = ("composer('push the yellow block to the right side of the table while staying away "
            "from the pink block')")
    assert fold_avoided(instruction, kept) is None
    assert fold_avoided("go to the front side of the table while avoiding the pink block",
                        "composer('move to the front side of the table')\n"
                        "composer('go around the pink block')") == (
        "composer('move to the front side of the table while staying away from the pink "
        "block')")


def test_an_object_referred_to_again_is_not_only_to_be_avoided() -> None:
    assert avoided_objects("move to the back side of the table while staying away from the red "
                           "block, and then hover 10cm over it") == set()


def test_a_place_the_instruction_does_not_name_is_named() -> None:
    instruction = ("push the pink block to the right side of the table and keep it away from "
                   "the blue block")
    code = ("composer('push the pink block to the right side of the table')\n"
            "composer('push the pink block to the back side of the table while staying away "
            "from the blue block')")
    assert {k for k, _ in _gaps(instruction, code)} == {UNNAMED_PLACE}


def test_the_review_sends_an_unasked_grasp_back_with_it_named() -> None:
    review = PlanReview(PUSH_AWAY, max_attempts=3, post_conditions=False)
    plan = ("composer('grasp the green block')\ncomposer('push the green block to the front "
            "right corner of the table while staying away from the yellow block')")
    code, correction, _ = review.review(plan, attempt=1)
    assert code == plan and correction is not None
    assert "'grasp the green block'" in correction and "asks no grasp" in correction
    fixed = ("composer('push the green block to the front right corner of the table while "
             "staying away from the yellow block')")
    assert review.review(fixed, attempt=2) == (fixed, None, [])


@pytest.mark.parametrize("task", sorted(TASKS))
def test_reference_plans_do_nothing_unasked(task: str) -> None:
    """Neither the templates nor the dev rewordings send a reference plan back."""
    for instruction, code in reference_plans(task):
        assert _gaps(instruction, code) == set(), instruction
        assert fold_avoided(instruction, code) is None, instruction
        assert named_places_only(instruction, code) is None, instruction
    for seed in range(6):
        attrs = TASKS[task].sample_attributes(episode_rng(task, "seen", seed), "seen")
        code = with_expectation(TASKS[task].reference(attrs), task, attrs).code(
            "planner", TASKS[task].instruction(attrs))
        worded = paraphrase(task, attrs, "dev", seed)
        assert _gaps(worded, code) == set(), worded
        assert fold_avoided(worded, code) is None, worded
        assert named_places_only(worded, code) is None, worded


@pytest.mark.parametrize("name", sorted(ENTRIES))
def test_multistep_reference_plans_do_nothing_unasked(name: str) -> None:
    entry = ENTRIES[name]
    for seed in range(4):
        attrs = entry.sample_attributes(episode_rng(name, "seen", seed), "seen")
        instruction = entry.instruction(attrs)
        code = entry.reference(attrs).code("planner", instruction)
        assert _gaps(instruction, code) == set(), instruction
        assert fold_avoided(instruction, code) is None, instruction
        assert named_places_only(instruction, code) is None, instruction


def test_an_avoidance_no_sub_task_names_is_said_in_the_motion() -> None:
    """The clause checklist asked once; the plan still never names the block to avoid."""
    instruction = ("move the yellow block to the front right corner of the table with pushes, "
                   "steering it around the pink block")
    code = ("composer('move the yellow block to the front right corner of the table with "
            "pushes')\ncomposer('back to default pose')")
    assert fold_avoided(instruction, code) == (
        "composer('move the yellow block to the front right corner of the table with pushes "
        "while staying away from the pink block')\ncomposer('back to default pose')")


def test_a_wide_berth_is_an_avoidance_and_a_visit_to_the_block_is_mended() -> None:
    instruction = ("get the brown block to the front right corner of the table by pushing, and "
                   "give the blue block a wide berth")
    assert avoided_objects(instruction) == {"blue block"}
    code = ("composer('push the brown block to the front right corner of the table')\n"
            "composer('move to a point 10cm above the blue block')\n"
            "expect(above('gripper', 'blue block', cm=10))")
    assert fold_avoided(instruction, code) == (
        "composer('push the brown block to the front right corner of the table while staying "
        "away from the blue block')")
