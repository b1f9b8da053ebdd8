"""A plan kept to the one table place its instruction names, a repeated motion said once."""

from __future__ import annotations

from voxposer.lmp.plan_places import named_places_only

SAID = "push the pink block to the right side of the table and keep it away from the blue block"


def test_an_unnamed_place_becomes_the_named_one_and_the_repeat_merges() -> None:
    code = ("composer('push the pink block to the right side of the table')\n"
            "expect(moved('pink block'))\n"
            "composer('push the pink block to the back side of the table while staying away "
            "from the blue block')\n"
            "expect(away('pink block', 'blue block'))\n"
            "composer('back to default pose')")
    assert named_places_only(SAID, code) == (
        "composer('push the pink block to the right side of the table while staying away from "
        "the blue block')\nexpect(moved('pink block'))\nexpect(away('pink block', 'blue block'))"
        "\ncomposer('back to default pose')")


def test_plans_on_named_places_and_instructions_with_two_places_are_left_alone() -> None:
    kept = ("composer('push the pink block to the right side of the table while staying away "
            "from the blue block')")
    assert named_places_only(SAID, kept) is None
    two = "move to the back side of the table at faster speed in the left side of the table"
    assert named_places_only(two, "composer('move to the front side of the table')") is None
    assert named_places_only("hover over the blue block", "composer('move to the front side "
                             "of the table')") is None
