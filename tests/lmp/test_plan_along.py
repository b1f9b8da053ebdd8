"""A push along a line planned as one sub-task becomes the examples' two pushes."""

from __future__ import annotations

from voxposer.lmp.plan_along import push_along_ends
from voxposer.lmp.plan_pipeline import complete_plan
from voxposer.lmp.registry import LMPConfig

OBJECTS = ("table", "gripper", "blue block", "green block", "yellow line", "green line")


def test_one_push_along_the_line_becomes_near_end_then_far_end() -> None:
    code = ("composer('slide the blue block along the yellow line')\n"
            "expect(moved('blue block', cm=10))\ncomposer('back to default pose')")
    out = push_along_ends(code, OBJECTS)
    assert out == ("composer('push the blue block to the near end of the yellow line')\n"
                   "composer('push the blue block to the far end of the yellow line')\n"
                   "expect(moved('blue block', cm=10))\n"
                   "expect(along('blue block', 'yellow line'))\n"
                   "composer('back to default pose')")


def test_a_stated_along_is_kept_once_and_plans_already_split_or_elsewhere_are_left() -> None:
    code = ("composer('nudge the green block along the green line')\n"
            "expect(along('green block', 'green line'))")
    out = push_along_ends(code, OBJECTS) or ""
    assert out.count("along(") == 1 and "far end of the green line" in out
    split = ("composer('push the blue block to the near end of the green line')\n"
             "composer('push the blue block to the far end of the green line')")
    point = "composer('push the blue block to a point 5cm along the green line')"
    unknown = "composer('slide the red block along the yellow line')"
    for plan in (split, point, unknown, "x = 1\ncomposer('slide the blue block along the green line')"):
        assert push_along_ends(plan, OBJECTS) is None, plan


def test_the_pipeline_splits_the_push_and_records_why() -> None:
    events: list[dict] = []
    out = complete_plan("slide the blue block along the yellow line",
                        "composer('slide the blue block along the yellow line')", LMPConfig(),
                        OBJECTS, lambda **e: events.append(e))
    assert "near end of the yellow line" in out and "far end of the yellow line" in out
    assert events[0]["why"] == "a sub-task pushed along a line in one motion"
    off = complete_plan("x", "composer('slide the blue block along the yellow line')",
                        LMPConfig(push_along_ends=False, derived_conditions=False), OBJECTS,
                        lambda **e: None)
    assert off == "composer('slide the blue block along the yellow line')"
