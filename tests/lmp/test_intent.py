"""Intent checks: the planner's post-conditions measured on a box scene."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from voxposer.lmp import make_tabletop_scene
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.intent import IntentChecks


@pytest.fixture
def checks() -> IntentChecks:
    return IntentChecks(LMPAPI(make_tabletop_scene()))


def helpers(checks: IntentChecks) -> dict:
    return checks.namespace(lambda fn: fn)


def test_moved_measures_the_displacement_since_the_sub_task_began(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    checks.begin_subtask("push the blue block to the left")
    scene.move("blue block", (0.0, -0.06, 0.0))
    assert h["moved"]("blue block", toward="left").held
    assert h["moved"]("the blue cube", cm=5).held  # synonyms, 6 cm in all
    wrong_way = h["moved"]("blue block", toward="right")
    assert not wrong_way.held and "-6.0 cm toward right" in wrong_way.measured
    assert not h["moved"]("blue block", toward="left", cm=7).held
    assert not h["moved"]("green block").held  # it stayed


def test_a_drawer_moves_by_its_front_face(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    closed = scene.box("top drawer")
    open_lo = closed.lo + np.array([0.0, -0.08, 0.0])  # pulled out 8 cm toward -y
    scene.set_box("top drawer", open_lo, closed.hi)  # the cameras see its front and its top
    checks.begin_subtask("close the top drawer by pushing")
    scene.set_box("top drawer", closed.lo, closed.hi)  # pushed in: only the front in view
    cond = h["moved"]("top drawer", cm=6)  # the visible box's centre moved only 4 cm
    assert cond.held and "moved 8.0 cm" in cond.measured
    assert h["moved"]("top drawer", toward="right", cm=6).held  # in: +y (it opens toward −y)
    scene.move("blue block", (0.0, 0.03, 0.0))
    assert "moved 3.0 cm" in h["moved"]("blue block").measured  # a block: by its centre


def test_near_on_and_above_read_the_scene_now(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    blue = scene.detect("blue block")
    scene.set_ee(blue.position + np.array([0.0, 0.0, 0.12]))
    assert h["above"]("gripper", "blue block").held
    assert h["above"]("gripper", "blue block", cm=10).held  # 12 cm centre = 9.5 cm over the top
    assert not h["above"]("gripper", "blue block", cm=20).held
    assert h["near"]("gripper", "blue block", cm=10).held is True  # a bool, for JSON
    assert not h["near"]("gripper", "blue block", cm=5).held
    scene.set_ee((0.0, 0.30, 0.10))  # over the right side of the table
    assert h["on"]("gripper", "table", "right side").held
    assert not h["on"]("gripper", "table", "left side").held
    assert not h["above"]("gripper", "blue block").held


def test_away_uses_the_executed_path_not_only_where_it_ended(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    green = scene.detect("green block").position
    checks.begin_subtask("move past the green block")
    far = green + np.array([0.0, 0.3, 0.0])
    scene.set_ee(far)
    assert h["away"]("gripper", "green block", cm=10).held  # no path known: where it is now
    brushing = np.stack([green + np.array([0.0, 0.04, 0.0]), far])  # 1.5 cm from its face
    checks.add_execution(SimpleNamespace(trace=list(brushing), entity="gripper",
                                         entity_path=brushing))
    close = h["away"]("gripper", "green block", cm=10)
    assert not close.held and "closest 1.5 cm" in close.measured


def test_far_is_where_the_hand_ends_not_the_path_it_left_by(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    green = scene.detect("green block").position
    checks.begin_subtask("move away from the green block")
    start = green + np.array([0.0, 0.04, 0.0])  # 1.5 cm from its face, where the push ended
    end = green + np.array([0.0, 0.0, 0.175])  # 15 cm over its top face
    scene.set_ee(end)
    path = np.stack([start, end])
    checks.add_execution(SimpleNamespace(trace=list(path), entity="gripper", entity_path=path))
    left = h["far"]("gripper", "green block")
    assert left.held and "ends 15.0 cm" in left.measured
    assert not h["away"]("gripper", "green block", cm=10).held  # the path began beside it
    scene.set_ee(green + np.array([0.0, 0.0, 0.10]))  # 7.5 cm over it
    assert not h["far"]("gripper", "green block").held
    assert h["far"]("gripper", "green block", cm=7).held


def test_a_condition_may_name_an_object_as_the_plan_described_it(checks: IntentChecks) -> None:
    """parse_query_obj resolved "block next to the blue block" to the green block: a condition
    naming the description measures the green block, not the blue one its words hold."""
    h, scene = helpers(checks), checks.api.scene
    checks.alias("the block next to the blue block", "green block")
    checks.begin_subtask("push the block next to the blue block to the left")
    scene.move("green block", (0.0, -0.06, 0.0))
    assert h["moved"]("block next to the blue block", toward="left").held
    assert not h["moved"]("blue block").held
    with pytest.raises(Exception, match="unknown object"):
        checks._name("block farthest to the left")  # never resolved: no guess


def test_holding_needs_a_closed_gripper_at_the_object(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    scene.set_ee(scene.detect("yellow block").position)
    assert not h["holding"]("yellow block").held  # open
    scene.gripper = 1.0
    assert h["holding"]("yellow block").held
    assert not h["holding"]("pink block").held


def test_expect_records_results_and_a_bad_condition_never_breaks_the_plan(
        checks: IntentChecks) -> None:
    h = helpers(checks)
    checks.begin_subtask("move to the right side of the table")
    checks.api.scene.set_ee((0.0, 0.30, 0.10))
    assert h["expect"](h["on"]("gripper", "table", "right side")) is True
    assert checks.verdict() is True
    bad = h["moved"]("unicorn")  # unknown object: recorded as unevaluated, not raised
    assert h["expect"](bad, True) is False  # a bare bool is not a condition either
    assert [r.error for r in checks.results] == [False, True, True]
    assert "could not evaluate" in checks.results[1].measured
    assert checks.verdict() is True  # unevaluated conditions do not count
    assert h["expect"](h["on"]("gripper", "table", "left side")) is False
    assert checks.verdict() is False
    (failed,) = checks.failed()
    assert failed.subtask == "move to the right side of the table"
    assert failed.condition == "on('gripper', 'table', 'left side')"


def test_no_condition_stated_is_no_verdict(checks: IntentChecks) -> None:
    assert checks.verdict() is None and checks.failed() == []


def test_on_a_side_of_a_block_means_beside_it(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    brown = scene.detect("brown block")
    front = brown.position + np.array([0.075, 0.0, 0.0])  # 5 cm beyond its front face
    scene.set_ee(front)
    assert h["on"]("gripper", "brown block", "front side").held
    assert not h["on"]("gripper", "brown block", "back side").held
    assert not h["on"]("gripper", "brown block", "left side").held
    scene.set_ee(front + np.array([0.0, 0.10, 0.0]))  # in front, but 10 cm off to the right
    assert not h["on"]("gripper", "brown block", "front side").held
    scene.set_ee(brown.position + np.array([0.30, 0.0, 0.0]))  # far in front
    assert not h["on"]("gripper", "brown block", "front").held


def test_released_is_an_open_hand_or_the_object_away_from_it(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    scene.set_ee(scene.detect("yellow block").position)
    scene.gripper = 1.0
    assert not h["released"]("yellow block").held  # closed around it: still held
    assert h["released"]("pink block").held  # closed, but not around the pink block
    scene.gripper = 0.0
    cond = h["released"]("yellow block")
    assert cond.held and "gripper open" in cond.measured
