"""A speed zone planned as a second destination is folded back into the motion to the place."""

from __future__ import annotations

import pytest

from voxposer.lmp.plan_pipeline import complete_plan
from voxposer.lmp.plan_zone import zone_not_destination
from voxposer.lmp.registry import LMPConfig

SAID = ("move over to the back left corner of the table, and over the back side of the table "
        "change your speed to faster speed")


def test_the_zone_said_as_a_destination_becomes_the_speed_of_the_motion() -> None:
    """Dev record (ad-hoc seed 27, an extra dev phrasing): the hand ended 19 cm from the corner
    at the default speed."""
    code = ("composer('move to the back left corner of the table')\n"
            "expect(on('gripper', 'table', 'back left corner'))\n"
            "composer('move to the back side of the table while moving at faster speed')\n"
            "expect(on('gripper', 'table', 'back side'))")
    assert zone_not_destination(SAID, code) == (
        "composer('move to the back left corner of the table at faster speed in the back side "
        "of the table')\nexpect(on('gripper', 'table', 'back left corner'))")
    slow = SAID.replace("faster speed", "a quarter of the speed")
    out = zone_not_destination(slow, code.replace("faster speed", "a quarter of the speed"))
    assert out is not None and "corner of the table at a quarter of the speed in the back side" \
        in out


@pytest.mark.parametrize(("instruction", "code"), [
    # already said as the examples say it
    (SAID, "composer('move to the back left corner of the table at faster speed in the back "
           "side of the table')"),
    # no speed in the instruction: a second place is not a zone
    ("move to the back left corner of the table, then to the back side of the table",
     "composer('move to the back left corner of the table')\n"
     "composer('move to the back side of the table')"),
    # the motion to the zone says no speed (a place to go, as far as the plan says)
    (SAID, "composer('move to the back left corner of the table')\n"
           "composer('move to the back side of the table')"),
    # two other places: which motion the speed belongs to is not known
    ("go to the front right corner and then the back left corner of the table, at faster speed "
     "over the back side of the table",
     "composer('move to the front right corner of the table')\n"
     "composer('move to the back side of the table at faster speed')\n"
     "composer('move to the back left corner of the table')"),
])
def test_plans_without_the_misreading_are_left(instruction: str, code: str) -> None:
    assert zone_not_destination(instruction, code) is None


def test_the_pipeline_folds_the_zone_and_asks_the_speed_inside_it() -> None:
    code = ("composer('move to the back left corner of the table')\n"
            "composer('move to the back side of the table while moving at faster speed')")
    events: list[dict[str, str]] = []
    out = complete_plan(SAID, code, LMPConfig(), ("table", "gripper"),
                        lambda **e: events.append(e))
    assert out.splitlines() == [
        "composer('move to the back left corner of the table at faster speed in the back side "
        "of the table')", "expect(speed('gripper', 2, inside='back side'))"]
    assert events[0]["why"] == "a sub-task went to the table part the instruction says a speed in"
    off = complete_plan(SAID, code, LMPConfig(zone_not_destination=False), ("table", "gripper"),
                        lambda **e: None)
    assert "move to the back side of the table" in off
