"""Intent checks over the executed path: ``away`` between two objects' faces, ``passed_on`` (the
side a path kept while passing a block) and ``speed`` (the end effector's measured speed,
overall or near an object), on a box scene with constructed traces."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from voxposer.lmp import make_tabletop_scene
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.intent import IntentChecks
from voxposer.lmp.intent_paths import box_gap, compact_gap, is_compact

EE_SPEED = 0.25  # m/s at speed scale 1


@pytest.fixture
def checks() -> IntentChecks:
    c = IntentChecks(LMPAPI(make_tabletop_scene()))
    c.ee_speed = EE_SPEED
    return c


def helpers(checks: IntentChecks) -> dict:
    return checks.namespace(lambda fn: fn)


def line(a: np.ndarray, b: np.ndarray, n: int) -> np.ndarray:
    return np.linspace(a, b, n)


def executed(checks: IntentChecks, path: np.ndarray, dt: float = 0.02, entity: str = "gripper",
             entity_path: np.ndarray | None = None) -> None:
    checks.add_execution(SimpleNamespace(
        trace=list(path), trace_time=list(np.arange(len(path)) * dt), entity=entity,
        entity_path=path if entity_path is None else entity_path))


def test_away_between_two_blocks_is_measured_between_their_faces(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    green = scene.detect("green block").position
    checks.begin_subtask("push the blue block past the green block")
    # the blue block's centre passes 8 cm from the green block's centre: 3 cm between faces
    path = line(green + np.array([-0.2, 0.08, 0.0]), green + np.array([0.2, 0.08, 0.0]), 20)
    executed(checks, path + np.array([0.0, 0.0, 0.05]), entity="blue block", entity_path=path)
    assert not h["away"]("blue block", "green block").held  # default 4 cm
    assert h["away"]("blue block", "green block", cm=2.5).held
    assert "closest 3.0 cm" in h["away"]("blue block", "green block").measured


def test_two_blocks_corner_to_corner_are_as_far_apart_as_their_centres_say(
        checks: IntentChecks) -> None:
    """Centres 9.1 cm apart on the diagonal: the axis-aligned boxes are 2.1 cm apart at their
    corners, the blocks (5 cm) 4.1 cm by their footprints' circles, as when side by side."""
    h, scene = helpers(checks), checks.api.scene
    green = scene.detect("green block").position
    checks.begin_subtask("push the blue block past the green block")
    off = 0.091 / np.sqrt(2.0)
    turn = np.linspace(np.pi, 0.0, 60)  # half way round it, 9.1 cm from its centre
    path = green + 0.091 * np.stack([np.cos(turn), np.sin(turn), 0.0 * turn], axis=1)
    corner = np.array([off, off, 0.0]) + green
    executed(checks, path + np.array([0.0, 0.0, 0.05]), entity="blue block", entity_path=path)
    cond = h["away"]("blue block", "green block")
    assert cond.held, cond.measured
    assert "closest 4.1 cm" in cond.measured
    # from perceived centres, so no slack: 4.1 cm is not the 4.3 cm asked (the gripper's
    # distance to a box's faces keeps half a voxel of slack)
    assert h["away"]("blue block", "green block", cm=4.0).held
    assert not h["away"]("blue block", "green block", cm=4.3).held
    assert box_gap(corner[None], *scene.detect("green block").aabb,
                   np.full(3, 0.025))[0] == pytest.approx(0.021, abs=0.002)


def test_compact_gap_ignores_a_turned_blocks_larger_box() -> None:
    half = np.array([0.025, 0.025, 0.025])
    lo, hi = np.array([-0.025, -0.025, 0.0]), np.array([0.025, 0.025, 0.05])
    points = np.array([[0.09, 0.0, 0.025], [0.0, 0.0, 0.2], [0.0, 0.0, 0.025]])
    assert compact_gap(points, half, lo, hi) == pytest.approx([0.04, 0.125, 0.0])
    turned = np.array([0.0354, 0.0354, 0.025])  # the 45°-turned block's box
    assert is_compact(-turned, turned) and is_compact(lo, hi)
    assert not is_compact(np.zeros(3), np.array([0.3, 0.05, 0.1]))  # a line, a drawer


def test_an_objects_path_between_replans_counts(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    green = scene.detect("green block").position
    checks.begin_subtask("push the blue block past the green block")
    # observed only 15 cm before and after passing: the closest approach lies between samples
    path = np.stack([green + [-0.15, 0.08, 0.0], green + [0.15, 0.08, 0.0]])
    executed(checks, path + np.array([0.0, 0.0, 0.05]), entity="blue block", entity_path=path)
    assert not h["away"]("blue block", "green block", cm=4).held
    assert "closest 3.0 cm" in h["away"]("blue block", "green block").measured


def test_passed_on_a_side_needs_the_path_beyond_that_face_while_level(checks: IntentChecks
                                                                       ) -> None:
    h, scene = helpers(checks), checks.api.scene
    pink = scene.detect("pink block")
    (_, hi), c = pink.aabb, pink.position
    checks.begin_subtask("move past the pink block on its left")
    left = line(c + np.array([-0.3, -0.06, 0.0]), c + np.array([0.3, -0.06, 0.0]), 40)
    executed(checks, left)
    assert h["passed_on"]("gripper", "pink block", "left side").held
    assert not h["passed_on"]("gripper", "pink block", "right side").held
    checks.begin_subtask("move past the pink block, cutting through its right half")
    executed(checks, left + np.array([0.0, 0.08, 0.0]))  # 2 cm right of its centre
    cut = h["passed_on"]("gripper", "pink block", "left side")
    assert not cut.held and "across" in cut.measured
    checks.begin_subtask("never near it")
    executed(checks, line(c + np.array([-0.3, 0.3, 0.0]), c + np.array([-0.2, 0.3, 0.0]), 10))
    far = h["passed_on"]("gripper", "pink block", "left side")
    assert not far.held and far.measured.startswith("never passed")
    checks.begin_subtask("over the top")
    over = line(c + np.array([-0.3, 0.0, hi[2] - c[2] + 0.04]),
                c + np.array([0.3, 0.0, hi[2] - c[2] + 0.04]), 40)
    executed(checks, over)
    assert h["passed_on"]("gripper", "pink block", "top").held
    checks.begin_subtask("through it, level with its middle")
    executed(checks, over - np.array([0.0, 0.0, hi[2] - c[2] + 0.04]))
    assert not h["passed_on"]("gripper", "pink block", "top").held


def test_speed_reads_the_median_speed_over_the_default(checks: IntentChecks) -> None:
    h = helpers(checks)
    checks.begin_subtask("move slowly")
    step = EE_SPEED * 0.25 * 0.02  # a quarter of the default speed at 50 Hz
    executed(checks, np.array([-0.3, 0.0, 0.2]) + np.outer(np.arange(120), [step, 0.0, 0.0]))
    assert h["speed"]("gripper", 0.25).held
    assert not h["speed"]("gripper", 1.0).held
    assert not h["speed"]("gripper", 2).held
    assert "0.25x default" in h["speed"]("gripper", 0.25).measured


def test_speed_near_an_object_counts_only_the_zone(checks: IntentChecks) -> None:
    h, scene = helpers(checks), checks.api.scene
    green = scene.detect("green block").position
    start = green + np.array([-1.1, 0.0, 0.03])
    fast = start + np.outer(np.arange(200), [EE_SPEED * 0.02, 0.0, 0.0])  # 1 m at 1x, far
    slow = fast[-1] + np.outer(np.arange(1, 101), [EE_SPEED * 0.25 * 0.02, 0.0, 0.0])  # 12 cm
    checks.begin_subtask("slow near the green block")
    executed(checks, np.vstack([fast, slow]))
    assert h["speed"]("gripper", 0.25, near="green block", cm=5).held
    assert not h["speed"]("gripper", 1.0, near="green block", cm=5).held
    assert h["speed"]("gripper", 1.0).held  # over the whole path most of it ran at 1x
    assert h["speed"]("gripper", 1.0, near="blue block", cm=5).measured.startswith("hardly")

def test_speed_over_a_table_part_counts_only_that_part(checks: IntentChecks) -> None:
    h = helpers(checks)
    fast = line(np.array([0.05, 0.0, 0.1]), np.array([-0.1, 0.0, 0.1]), 31)  # 5 mm at 50 Hz: 1x
    slow = line(fast[-1], np.array([-0.45, 0.0, 0.1]), 281)[1:]  # 1.25 mm per step: 0.25x
    checks.begin_subtask("slow over the back side")
    executed(checks, np.vstack([fast, slow]))
    assert h["speed"]("gripper", 0.25, inside="back side").held
    assert not h["speed"]("gripper", 1.0, inside="back side").held
    assert not h["speed"]("gripper", 0.25, inside="front side").held
    # ``side`` is the same argument under the name people (and the model) use for it
    assert h["speed"]("gripper", 0.25, side="back side").held
    assert "over the back side" in h["speed"]("gripper", 0.25, side="back side").measured
    both = h["speed"]("gripper", 0.25, inside="back side", side="front side")
    assert both.error and "two table parts" in both.measured


def test_speed_without_the_robots_default_speed_is_not_evaluated() -> None:
    checks = IntentChecks(LMPAPI(make_tabletop_scene()))
    cond = helpers(checks)["speed"]("gripper", 0.5)
    assert cond.error and not cond.held and "default speed is unknown" in cond.measured


def test_an_obstacle_pushed_aside_counts_where_it_was(checks: IntentChecks) -> None:
    """The blue block brushes the green one (2 cm between faces), which then slides 5 cm away:
    measured against where the green block is now alone, the pass would look 7 cm clear."""
    h, scene = helpers(checks), checks.api.scene
    green = scene.detect("green block").position
    checks.begin_subtask("push the blue block past the green block")
    path = line(green + np.array([-0.2, 0.07, 0.0]), green + np.array([0.2, 0.07, 0.0]), 20)
    executed(checks, path + np.array([0.0, 0.0, 0.05]), entity="blue block", entity_path=path)
    scene.move("green block", [0.0, -0.05, 0.0])
    cond = h["away"]("blue block", "green block")
    assert not cond.held and "closest 2.0 cm" in cond.measured


def test_along_a_line_needs_travel_along_its_axis_not_onto_it(checks: IntentChecks) -> None:
    """Lines of the box scene run along y, 20 cm long: a push onto the line's middle from the
    side moves the block 12 cm but only across; one down the line covers 16 cm of it."""
    h, scene = helpers(checks), checks.api.scene
    c = scene.detect("yellow line").position
    checks.begin_subtask("push the blue block along the yellow line")
    onto = line(c + np.array([0.12, 0.0, 0.025]), c + np.array([0.0, 0.02, 0.025]), 12)
    executed(checks, onto, entity="blue block", entity_path=onto)
    cond = h["along"]("blue block", "yellow line")
    assert not cond.held and "needs 10.0" in cond.measured
    checks.begin_subtask("push the blue block along the yellow line")
    down = line(c + np.array([0.01, -0.08, 0.025]), c + np.array([0.01, 0.08, 0.025]), 17)
    executed(checks, down, entity="blue block", entity_path=down)
    cond = h["along"]("blue block", "yellow line")
    assert cond.held and "went 16.0 cm" in cond.measured
    assert not h["along"]("blue block", "yellow line", cm=18).held
