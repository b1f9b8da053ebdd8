"""The pixel perception's hard cases: a gray block touching the gray robot (tracked from where
it was), a block on its own colour's noisy line (told apart by height), a noisy line's stretch (no
block of its colour), and a noisy table
inside the box of an absent cabinet (not a cabinet)."""

from __future__ import annotations

import numpy as np

from voxposer.catalog import COLOR_NAMES
from voxposer.perception.cabinet_fit import fit_cabinet
from voxposer.perception.colour_names import GRAY
from voxposer.perception.colour_objects import find_blocks_and_lines, line_prior
from voxposer.tabletop import CABINET_POSITION, CABINET_SIZE


def _cube(centre: tuple[float, float, float], rng: np.random.Generator, n: int = 600
          ) -> np.ndarray:
    return np.asarray(centre) + rng.uniform(-0.025, 0.025, (n, 3))


def test_a_gray_block_in_the_gripper_is_tracked_from_where_it_was() -> None:
    rng = np.random.default_rng(0)
    block = _cube((0.1, -0.1, 0.025), rng)
    # the gripper closing on it: the hand resting on its top face, rising above it (one gray
    # cluster with the block), and a finger 1.2 cm beside it
    hand = np.column_stack([rng.uniform(0.07, 0.13, 900), rng.uniform(-0.13, -0.07, 900),
                            rng.uniform(0.051, 0.2, 900)])
    finger = np.column_stack([rng.uniform(0.09, 0.11, 200), rng.uniform(-0.145, -0.137, 200),
                              rng.uniform(0.01, 0.06, 200)])
    fingers = np.vstack([hand, finger])
    points = np.vstack([block, fingers])
    colours = np.full(len(points), GRAY, dtype=np.int32)
    assert "gray block" not in find_blocks_and_lines(points, colours)  # merged with the robot
    found = find_blocks_and_lines(points, colours, {"gray block": np.array([0.11, -0.09, 0.03])})
    centre = points[found["gray block"]].mean(axis=0)
    assert np.linalg.norm(centre - [0.1, -0.1, 0.025]) < 0.01
    assert np.count_nonzero(found["gray block"] >= len(block)) < 0.1 * len(block)  # few finger


def test_a_block_on_its_own_colours_noisy_line_is_still_a_block() -> None:
    rng = np.random.default_rng(3)
    block = _cube((0.0, 0.0, 0.025), rng)
    # a 20 cm green line along y under it, its paint lifted 0-12 mm by depth noise
    line = np.column_stack([rng.uniform(-0.006, 0.006, 800), rng.uniform(-0.1, 0.1, 800),
                            np.abs(rng.normal(0.0, 0.006, 800))])
    points = np.vstack([block, line])
    colours = np.full(len(points), 1, dtype=np.int32)  # one colour word for both
    found = find_blocks_and_lines(points, colours)
    got = points[found["green block"]]
    assert np.linalg.norm(got[:, :2].mean(axis=0)) < 0.01 and np.ptp(got[:, 1]) < 0.07
    line_pts = points[found["green line"]]
    assert np.ptp(line_pts[:, 1]) > 0.12  # the line's two ends, either side of the block


def test_a_stretch_of_noisy_line_is_no_block_of_its_colour() -> None:
    """A green block cuts a yellow line in two; the depth noise lifts either piece's paint
    above the flat band, each piece compact: still one line and no yellow block."""
    rng = np.random.default_rng(4)
    block = _cube((0.005, 0.0, 0.025), rng)
    x = rng.uniform(-0.1, 0.1, 1200)
    x = x[np.abs(x - 0.005) > 0.03]  # under the green block: hidden
    line = np.column_stack([x, rng.uniform(-0.006, 0.006, len(x)),
                            0.002 + np.abs(rng.normal(0.0, 0.004, len(x)))])
    points = np.vstack([block, line])
    colours = np.r_[np.full(len(block), COLOR_NAMES.index("green")),
                    np.full(len(line), COLOR_NAMES.index("yellow"))].astype(np.int32)
    found = find_blocks_and_lines(points, colours)
    assert sorted(found) == ["green block", "yellow line"]
    assert np.ptp(points[found["yellow line"]][:, 0]) > 0.18  # both pieces, end to end


def test_a_block_far_from_its_prior_is_not_made_up() -> None:
    rng = np.random.default_rng(1)
    robot = np.column_stack([rng.uniform(-0.3, 0.0, 3000), rng.uniform(-0.05, 0.05, 3000),
                             rng.uniform(0.0, 0.5, 3000)])
    colours = np.full(len(robot), GRAY, dtype=np.int32)
    found = find_blocks_and_lines(robot, colours, {"gray block": np.array([0.2, 0.2, 0.025])})
    assert "gray block" not in found


def test_a_noisy_table_in_an_absent_cabinets_box_is_no_cabinet() -> None:
    rng = np.random.default_rng(2)
    cx, cy = CABINET_POSITION
    sx, sy = CABINET_SIZE[0] / 2, CABINET_SIZE[1] / 2
    n = 5000
    table = np.column_stack([rng.uniform(cx - sx, cx + sx, n), rng.uniform(cy - sy, cy + sy, n),
                             np.abs(rng.normal(0.0, 0.006, n))])  # a consumer camera's table
    normals = np.tile([0.0, 0.0, 1.0], (n, 1))
    assert not fit_cabinet(table, normals).present
    box = np.column_stack([rng.uniform(cx - sx, cx + sx, n), rng.uniform(cy - sy, cy + sy, n),
                           rng.uniform(0.0, CABINET_SIZE[2], n)])
    assert fit_cabinet(box, normals).present  # a real cabinet's points still are one


def test_a_gray_line_joined_by_other_flat_gray_points_is_kept_where_it_lay() -> None:
    rng = np.random.default_rng(3)
    line = np.column_stack([rng.uniform(-0.1, 0.1, 400), rng.uniform(-0.006, 0.006, 400),
                            rng.uniform(-0.002, 0.002, 400)])
    shadow = np.column_stack([rng.uniform(0.05, 0.15, 600), rng.uniform(0.01, 0.08, 600),
                              rng.uniform(-0.002, 0.002, 600)])  # flat, gray, touching it
    colours = np.full(len(line) + len(shadow), GRAY, dtype=np.int32)
    points = np.vstack([line, shadow])
    assert "gray line" not in find_blocks_and_lines(points, colours)  # no thin strip left
    prior = line_prior(line)
    found = find_blocks_and_lines(points, colours, {"gray line": prior})["gray line"]
    assert np.count_nonzero(found < len(line)) > 0.9 * len(line)
    assert np.count_nonzero(found >= len(line)) < 0.1 * len(shadow)


def test_a_gray_line_partly_covered_is_not_swapped_for_another_gray_strip() -> None:
    """A block over the gray line leaves two short fragments of it; a longer thin flat gray
    strip 40 cm away (the robot's base at table height) used to be taken for the line."""
    rng = np.random.default_rng(4)
    line = np.column_stack([rng.uniform(-0.1, 0.1, 400), rng.uniform(-0.006, 0.006, 400),
                            rng.uniform(-0.002, 0.002, 400)])
    prior = line_prior(line)
    uncovered = line[np.abs(line[:, 0]) > 0.07]  # two 3 cm ends
    strip = np.column_stack([rng.uniform(-0.5, -0.35, 150), rng.uniform(0.394, 0.406, 150),
                             rng.uniform(-0.002, 0.002, 150)])
    points = np.vstack([uncovered, strip])
    colours = np.full(len(points), GRAY, dtype=np.int32)
    without = find_blocks_and_lines(points, colours)["gray line"]
    assert np.all(without >= len(uncovered)), "the setting: without a prior, the strip wins"
    found = find_blocks_and_lines(points, colours, {"gray line": prior})["gray line"]
    assert np.all(found < len(uncovered)) and len(found) > 0.9 * len(uncovered)
