import numpy as np
import pytest

from voxposer.errors import GridError, OutOfWorkspaceError, VoxPoserError
from voxposer.geometry.voxel_grid import VoxelGrid


@pytest.fixture
def grid() -> VoxelGrid:
    return VoxelGrid((-0.5, -0.4, 0.0), (0.5, 0.6, 0.8), (100, 100, 80))


def test_resolution_and_size(grid: VoxelGrid) -> None:
    np.testing.assert_allclose(grid.resolution, [0.01, 0.01, 0.01])
    assert grid.size == 100 * 100 * 80


def test_world_voxel_round_trip_within_half_a_voxel(grid: VoxelGrid) -> None:
    rng = np.random.default_rng(0)
    pts = rng.uniform(grid.bounds_min, grid.bounds_max, size=(5000, 3))
    back = grid.voxel_to_world(grid.world_to_voxel(pts))
    assert np.all(np.abs(back - pts) <= grid.resolution / 2 + 1e-12)


def test_voxel_world_round_trip_is_exact(grid: VoxelGrid) -> None:
    rng = np.random.default_rng(1)
    vox = rng.integers(0, grid.shape, size=(1000, 3))
    np.testing.assert_array_equal(grid.world_to_voxel(grid.voxel_to_world(vox)), vox)


def test_rounding_rule_cells_are_half_open_and_upper_bound_is_last_cell(grid: VoxelGrid) -> None:
    lo = grid.bounds_min
    assert grid.world_to_voxel(lo).tolist() == [0, 0, 0]
    assert grid.world_to_voxel(lo + grid.resolution * [1.0, 2.0, 3.0]).tolist() == [1, 2, 3]
    assert grid.world_to_voxel(grid.bounds_max).tolist() == [99, 99, 79]


def test_outside_points_raise_unless_clipped(grid: VoxelGrid) -> None:
    outside = np.array([0.7, 0.0, 0.1])
    with pytest.raises(OutOfWorkspaceError, match=r"0\.7"):
        grid.world_to_voxel(outside)
    assert grid.world_to_voxel(outside, clip=True).tolist()[0] == 99
    with pytest.raises(OutOfWorkspaceError, match="finite"):
        grid.world_to_voxel([np.nan, 0, 0])


@pytest.mark.parametrize(
    ("lo", "hi", "shape", "match"),
    [
        ((0, 0, 0), (1, 0, 1), (10, 10, 10), "axis y"),
        ((0, 0, 0), (1, 1, 1), (10, 0, 10), "positive integers"),
        ((0, 0, 0), (1, 1, 1), (10, 10), "3 positive integers"),
        ((0, 0, np.nan), (1, 1, 1), (10, 10, 10), "finite"),
        ((0, 0), (1, 1, 1), (10, 10, 10), "bounds_min"),
    ],
)
def test_bad_grids_raise(lo, hi, shape, match) -> None:
    with pytest.raises(GridError, match=match):
        VoxelGrid(lo, hi, shape)


def test_cm2index_along_axes(grid: VoxelGrid) -> None:
    assert grid.cm2index(10, "x") == 10
    assert grid.cm2index(-7, "z") == -7
    np.testing.assert_array_equal(grid.cm2index(10, "left"), [0, -10, 0])
    np.testing.assert_array_equal(grid.cm2index(5, [0, 0, 2]), [0, 0, 5])


def test_cm2index_agrees_with_resolution_along_oblique_directions() -> None:
    grid = VoxelGrid((0, 0, 0), (1.0, 2.0, 0.5), (100, 100, 100))  # 1, 2 and 0.5 cm voxels
    rng = np.random.default_rng(2)
    for _ in range(200):
        direction = rng.normal(size=3)
        cm = rng.uniform(5, 40)
        disp = grid.cm2index(cm, direction)
        metres = disp * grid.resolution
        expected = cm / 100 * direction / np.linalg.norm(direction)
        assert np.all(np.abs(metres - expected) <= grid.resolution / 2 + 1e-12)


def test_index2cm_inverts_cm2index() -> None:
    grid = VoxelGrid((0, 0, 0), (1.0, 2.0, 0.5), (100, 100, 100))
    assert grid.index2cm(10, "y") == pytest.approx(20.0)
    rng = np.random.default_rng(3)
    for _ in range(100):
        direction = rng.normal(size=3)
        cm = rng.uniform(1, 30)
        disp = (cm / 100) * (direction / np.linalg.norm(direction)) / grid.resolution
        assert grid.index2cm(np.linalg.norm(disp), direction) == pytest.approx(cm)


def test_bad_directions_raise(grid: VoxelGrid) -> None:
    with pytest.raises(VoxPoserError, match="unknown direction 'sideways'"):
        grid.cm2index(3, "sideways")
    with pytest.raises(VoxPoserError, match="non-zero"):
        grid.cm2index(3, [0, 0, 0])


def test_points_to_occupancy_crops_outside_points(grid: VoxelGrid) -> None:
    pts = np.array([[0.0, 0.0, 0.1], [0.001, 0.002, 0.103], [5.0, 5.0, 5.0], [np.nan, 0, 0]])
    occ = grid.points_to_occupancy(pts)
    assert occ.shape == grid.shape
    assert occ.sum() == 1
    assert occ[tuple(grid.world_to_voxel(pts[0]))]


def test_points_to_occupancy_marks_each_points_own_voxel(grid: VoxelGrid) -> None:
    rng = np.random.default_rng(1)
    pts = rng.uniform(grid.bounds_min - 0.1, grid.bounds_max + 0.1, size=(2000, 3))
    pts[0] = grid.bounds_max  # the upper bound belongs to the last cell
    occ = grid.points_to_occupancy(pts)
    inside = np.all((pts >= grid.bounds_min) & (pts <= grid.bounds_max), axis=1)
    expected = np.zeros(grid.shape, bool)
    for p in pts[inside]:
        expected[tuple(grid.world_to_voxel(p))] = True
    assert np.array_equal(occ, expected)
    assert occ[tuple(np.array(grid.shape) - 1)]


def test_coarsen_keeps_box_and_covers_whole_fine_voxels(grid: VoxelGrid) -> None:
    coarse = grid.coarsen(2)
    assert coarse.shape == (50, 50, 40)
    np.testing.assert_allclose(coarse.resolution, 2 * grid.resolution)
    odd = VoxelGrid((0, 0, 0), (0.99, 0.99, 0.99), (99, 99, 99)).coarsen(2)
    assert odd.shape == (50, 50, 50)
    np.testing.assert_allclose(odd.resolution, [0.02, 0.02, 0.02])


def test_flat_voxels_are_the_raveled_clipped_voxels(grid: VoxelGrid) -> None:
    rng = np.random.default_rng(3)
    pts = rng.uniform(grid.bounds_min - 0.3, grid.bounds_max + 0.3, size=(20000, 3))
    pts[:3] = [grid.bounds_min, grid.bounds_max, grid.bounds_min + grid.resolution]  # edges
    expected = np.ravel_multi_index(tuple(grid.world_to_voxel(pts, clip=True).T), grid.shape)
    np.testing.assert_array_equal(grid.flat_voxels(pts), expected)
    assert grid.flat_voxels(np.zeros((0, 3))).shape == (0,)
    pts[7, 1] = np.nan
    with pytest.raises(OutOfWorkspaceError, match="finite"):
        grid.flat_voxels(pts)
