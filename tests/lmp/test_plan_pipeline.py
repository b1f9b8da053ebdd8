"""The plan's completions run in order, each behind its switch, each change recorded."""

from __future__ import annotations

from voxposer.lmp.plan_pipeline import STEPS, complete_plan
from voxposer.lmp.registry import LMPConfig

OBJECTS = ("table", "gripper", "blue block", "pink block")
PLAN = "composer('hover the pink block 10cm above the table')"


def test_every_step_has_a_switch_of_the_config() -> None:
    config = LMPConfig()
    assert all(isinstance(getattr(config, s.switch), bool) for s in STEPS)


def test_a_completion_feeds_the_next_and_each_change_is_recorded() -> None:
    events: list[dict] = []
    out = complete_plan("hover 10cm over the pink block", PLAN, LMPConfig(), OBJECTS,
                        lambda **e: events.append(e))
    # the hover becomes the hand's motion, and the derived conditions then measure it
    assert out == ("composer('move to a point 10cm above the pink block')\n"
                   "expect(above('gripper', 'pink block', cm=10))")
    assert [e["why"] for e in events] == ["a sub-task made the object hover",
                                          "post-conditions the sub-tasks' words ask"]


def test_a_switched_off_completion_does_not_run() -> None:
    events: list[dict] = []
    out = complete_plan("hover 10cm over the pink block", PLAN,
                        LMPConfig(hover_over=False, derived_conditions=False), OBJECTS,
                        lambda **e: events.append(e))
    assert out == PLAN and events == []
