import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from voxposer.errors import InvalidMapError, OutOfWorkspaceError
from voxposer.valuemaps import (
    TOP_DOWN_QUAT,
    ValueMapAPI,
    VoxelGrid,
    check_value_map,
    pointat2quat,
)


@pytest.fixture
def api() -> ValueMapAPI:
    grid = VoxelGrid((0, 0, 0), (1, 1, 1), (100, 100, 100))
    return ValueMapAPI(grid, ee_quat=lambda: (0.0, 0.0, 0.0, 1.0), gripper_state=lambda: 1.0)


def test_empty_maps_hold_the_paper_defaults(api: ValueMapAPI) -> None:
    assert api.get_empty_affordance_map().shape == (100, 100, 100)
    assert not api.get_empty_affordance_map().any()
    assert not api.get_empty_avoidance_map().any()
    assert np.all(api.get_empty_velocity_map() == 1)
    assert np.all(api.get_empty_gripper_map() == 1)
    rot = api.get_empty_rotation_map()
    assert rot.shape == (100, 100, 100, 4)
    np.testing.assert_array_equal(rot[3, 50, 99], [0, 0, 0, 1])


def test_set_voxel_by_radius_fills_a_sphere_not_a_box(api: ValueMapAPI) -> None:
    m = api.get_empty_affordance_map()
    api.set_voxel_by_radius(m, [50, 50, 50], 10, 1.0)  # 10 cm = 10 voxels
    filled = np.argwhere(m == 1)
    dist = np.linalg.norm(filled - 50, axis=1)
    assert dist.max() <= 10 + 1e-9
    assert m[60, 50, 50] == 1 and m[50, 40, 50] == 1
    assert m[57, 57, 57] == 0  # inside the bounding box, outside the sphere
    assert len(filled) == pytest.approx(4 / 3 * np.pi * 10**3, rel=0.05)


def test_set_voxel_by_radius_is_round_in_the_world_on_anisotropic_grids() -> None:
    grid = VoxelGrid((0, 0, 0), (1.0, 2.0, 0.5), (100, 100, 100))  # 1, 2, 0.5 cm voxels
    api = ValueMapAPI(grid)
    m = api.get_empty_avoidance_map()
    api.set_voxel_by_radius(m, (50, 50, 50), 10, 2.0)
    filled = grid.voxel_to_world(np.argwhere(m == 2))
    radius = np.linalg.norm(filled - grid.voxel_to_world([50, 50, 50]), axis=1)
    assert radius.max() <= 0.1 + 1e-9
    extent = filled.max(axis=0) - filled.min(axis=0)
    np.testing.assert_allclose(extent, [0.2, 0.2, 0.2], atol=0.021)


def test_set_voxel_by_radius_clips_at_the_border_and_sets_quaternions(api: ValueMapAPI) -> None:
    rot = api.get_empty_rotation_map()
    q = pointat2quat([1, 0, 0])
    api.set_voxel_by_radius(rot, np.array([0.2, 99.4, 0.0]), 3, q)  # floats are rounded
    np.testing.assert_allclose(rot[0, 99, 0], q, atol=1e-6)
    np.testing.assert_array_equal(rot[10, 99, 0], [0, 0, 0, 1])


def test_set_voxel_by_radius_bad_input(api: ValueMapAPI) -> None:
    m = api.get_empty_affordance_map()
    with pytest.raises(OutOfWorkspaceError, match=r"\[100, 5, 5\]"):
        api.set_voxel_by_radius(m, [100, 5, 5], 3, 1)
    with pytest.raises(InvalidMapError, match="radius_cm"):
        api.set_voxel_by_radius(m, [1, 5, 5], -3, 1)
    with pytest.raises(InvalidMapError, match="shape"):
        api.set_voxel_by_radius(np.zeros((10, 10, 10)), [1, 5, 5], 3, 1)


@pytest.mark.parametrize("vector", [(0, 0, -1), (1, 0, 0), (0, -1, 0), (0, 0, 1), (1, 1, -1)])
def test_pointat2quat_points_the_approach_axis(vector) -> None:
    q = pointat2quat(vector)
    assert np.linalg.norm(q) == pytest.approx(1.0)
    approach = Rotation.from_quat(q).apply([0, 0, 1])
    np.testing.assert_allclose(approach, np.asarray(vector) / np.linalg.norm(vector), atol=1e-9)


def test_pointat2quat_down_is_the_top_down_grasp() -> None:
    q = pointat2quat([0, 0, -1])
    np.testing.assert_allclose(q, TOP_DOWN_QUAT, atol=1e-12)
    np.testing.assert_allclose(Rotation.from_quat(q).apply([0, 0, 1]), [0, 0, -1], atol=1e-12)


def test_check_value_map_rejects_bad_maps(api: ValueMapAPI) -> None:
    grid = api.grid
    with pytest.raises(InvalidMapError, match=r"shape \(10, 10, 10\); expected \(100, 100, 100\)"):
        check_value_map("affordance", np.zeros((10, 10, 10)), grid)
    with pytest.raises(InvalidMapError, match="dtype"):
        check_value_map("avoidance", np.zeros(grid.shape, dtype=object), grid)
    bad = np.zeros(grid.shape, np.float32)
    bad[1, 2, 3] = np.nan
    with pytest.raises(InvalidMapError, match=r"NaN or inf \(first at voxel \[1, 2, 3\]\)"):
        check_value_map("velocity", bad, grid)
    with pytest.raises(InvalidMapError, match="unknown map kind 'colour'"):
        check_value_map("colour", bad, grid)
    with pytest.raises(InvalidMapError, match="numpy array"):
        check_value_map("gripper", [[1]], grid)
    with pytest.raises(InvalidMapError, match=r"expected \(100, 100, 100, 4\)"):
        check_value_map("rotation", np.zeros(grid.shape), grid)
    assert check_value_map("gripper", np.zeros(grid.shape, bool), grid).dtype == np.float32


def test_pointat2quat_turns_the_fingers_across_a_bar() -> None:
    from scipy.spatial.transform import Rotation

    from voxposer.geometry.frames import pointat2quat

    approach = np.array([1.0, 0.0, -1.0]) / np.sqrt(2)
    plain = Rotation.from_quat(pointat2quat(approach))
    turned = Rotation.from_quat(pointat2quat(approach, fingers=[1.0, 0.0, 0.0]))
    np.testing.assert_allclose(turned.apply([0, 0, 1]), approach, atol=1e-9)  # same approach
    np.testing.assert_allclose(plain.apply([1, 0, 0]), [0, 1, 0], atol=1e-9)  # fingers along y
    fingers = turned.apply([1, 0, 0])  # now across a bar along y, as near x as the tilt allows
    assert abs(fingers[1]) < 1e-9 and abs(abs(fingers @ [1, 0, 1]) / np.sqrt(2) - 1) < 1e-9
    # a fingers direction along the approach changes nothing
    np.testing.assert_allclose(pointat2quat(approach, fingers=approach), pointat2quat(approach))
