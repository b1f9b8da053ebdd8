"""On the table, the programs' API aims at the same places the benchmark checks."""

import numpy as np
import pytest

from voxposer.lmp.api import LMPAPI
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
