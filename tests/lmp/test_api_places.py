"""On the table, the programs' API aims at the same places the benchmark checks."""

import numpy as np
import pytest

from voxposer.lmp.api import LMPAPI, SideError
from voxposer.lmp.scene import make_tabletop_scene
from voxposer.places import PLACES


@pytest.fixture(scope="module")
def api() -> LMPAPI:
    return LMPAPI(make_tabletop_scene())


def _world(api: LMPAPI, voxel: np.ndarray) -> np.ndarray:
    return api.grid.voxel_to_world(voxel)


@pytest.mark.parametrize("place", list(PLACES.values()), ids=lambda p: p.words)
def test_point_on_the_table_is_the_places_point(api: LMPAPI, place) -> None:
    table = api.detect("table")
    p = _world(api, api.point_on(table, place.words))
    assert np.linalg.norm(p[:2] - np.asarray(place.point)) < 0.01  # within a voxel
    assert 0.0 < p[2] < 0.01  # on the surface
    assert place.contains(p[:2], 0.08)


def test_beside_the_tables_edge_reads_as_its_side_raised_by_the_distance(api: LMPAPI) -> None:
    table = api.detect("table")
    p = _world(api, api.point_beside(table, "front right", 9))
    assert np.linalg.norm(p[:2] - np.asarray(PLACES["front right corner of the table"].point)) < 0.01
    assert abs(p[2] - 0.09) < 0.01
    # other objects keep the face-offset meaning
    block = api.detect("blue block")
    q = _world(api, api.point_beside(block, "front", 5))
    assert abs(q[0] - (block.aabb_world[1][0] + 0.05)) < 0.01


def test_region_masks_are_the_places_bands_and_halves_stay_halves(api: LMPAPI) -> None:
    table = api.detect("table")
    grid = api.grid
    right = api.region_mask(table, "right side")
    y = _world(api, np.array([[0, j, 0] for j in range(grid.shape[1])]))[:, 1]
    assert np.array_equal(right[0, :, 0], y >= 0.15)
    assert right[:, :, 50].all(axis=0)[y >= 0.15].all()  # every x, every height
    corner = api.region_mask(table, "back left corner")
    pts = _world(api, np.argwhere(corner)[::50])
    assert np.all(pts[:, 0] <= -0.31) and np.all(pts[:, 1] <= -0.15)
    half = api.region_mask(table, "-y")  # an axis token: the table's centre split
    assert half[:, :, 0].sum() > corner[:, :, 0].sum()
    assert np.all(_world(api, np.argwhere(half)[::50])[:, 1] < 0.0)


@pytest.mark.parametrize(("phrase", "place"), [
    ("the far left corner of the table at the back", "back left corner of the table"),
    ("at its far end", "back side of the table"),
    ("the rear", "back side of the table"),
    ("the near side", "front side of the table"),
    ("top-left", "back left corner of the table"),
    ("back-left", "back left corner of the table"),
    ("leftmost", "left side of the table"),
    ("upper right corner", "back right corner of the table"),
    ("lower left corner", "front left corner of the table"),
    ("the side nearest to the robot", "back side of the table"),
])
def test_words_people_use_land_on_the_named_places(api: LMPAPI, phrase: str, place: str) -> None:
    table = api.detect("table")
    p = _world(api, api.point_on(table, phrase))
    assert np.linalg.norm(p[:2] - np.asarray(PLACES[place].point)) < 0.01
    mask = api.region_mask(table, phrase)
    assert np.array_equal(mask, api.region_mask(table, PLACES[place].words))
    q = _world(api, api.point_beside(table, phrase, 6))
    assert np.linalg.norm(q[:2] - np.asarray(PLACES[place].point)) < 0.01


def test_side_errors_reach_the_program_with_the_accepted_words(api: LMPAPI) -> None:
    table = api.detect("table")
    with pytest.raises(SideError, match=r"'right' and 'left' \(y axis\)"):
        api.point_on(table, "left right corner")
    with pytest.raises(SideError, match=r"unknown side word 'northern'.*rear.*leftmost"):
        api.region_mask(table, "northern edge")


def test_cm2index_takes_any_single_direction_word(api: LMPAPI) -> None:
    assert np.array_equal(api.cm2index(10, "rear"), api.cm2index(10, "back"))
    assert np.array_equal(api.cm2index(10, "leftmost"), api.cm2index(10, "left"))
    assert np.array_equal(api.cm2index(10, "Up"), api.cm2index(10, [0, 0, 1]))


def test_end_of_a_slanted_line_lies_on_its_axis_not_its_box(world) -> None:
    """A line 8.6° off the y axis: its box's end (the box's y edge at the centre's x) lies
    ~1 cm off the line's axis, ``end_of`` on it (within half a voxel)."""
    import math

    from voxposer.envs import SceneLayout
    from voxposer.lmp.api import LMPAPI
    from voxposer.lmp.scene import RobotScene
    from voxposer.pipeline import simulated_perceiver

    yaw = math.pi / 2 + 0.15
    layout = SceneLayout(poses={"yellow line": (-0.2, 0.0, yaw)}, extra_blocks=(0, 0),
                         extra_lines=(0, 0), cabinet=False)
    world.reset(np.random.default_rng(0), layout)
    api = LMPAPI(RobotScene(simulated_perceiver(world, "ground-truth"), world))
    line = api.detect("yellow line")
    u = np.array([math.cos(yaw), math.sin(yaw)])
    u = u if u[1] > 0 else -u  # toward the high (+y) end
    centre = world.object_position("yellow line")[:2]
    half = world.config.line_length / 2

    def off_axis(voxel) -> float:
        rel = api.grid.voxel_to_world(np.asarray(voxel, dtype=float))[:2] - centre
        return abs(float(rel @ np.array([-u[1], u[0]])))

    high, low_in = api.end_of(line, "high"), api.end_of(line, "low", cm_in=4)
    assert off_axis(high) < 0.005 and off_axis(low_in) < 0.005  # voxels are 1 cm
    far = api.grid.voxel_to_world(np.asarray(high, dtype=float))[:2]
    assert np.linalg.norm(far - (centre + half * u)) < 0.015
    boxed = line.position.copy()
    boxed[1] = line.aabb[1][1]
    assert off_axis(boxed) > 0.008  # the box's end: what the programs used before
    with pytest.raises(SideError, match="'low' or 'high'"):
        api.end_of(line, "far")
