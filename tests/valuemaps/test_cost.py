import numpy as np
import pytest

from voxposer.errors import ConfigError, EmptyAffordanceError, InvalidMapError, OutOfWorkspaceError
from voxposer.valuemaps import CostMapConfig, ValueMapAPI, VoxelGrid, compose_cost_map
from voxposer.valuemaps.cost import without_keep_out
from voxposer.valuemaps.keep_out import keep_out
from voxposer.valuemaps.voxel_ops import pool_max

GRID = VoxelGrid((0, 0, 0), (1, 1, 1), (100, 100, 100))
API = ValueMapAPI(GRID)
START = np.array([0.1, 0.1, 0.1])


def _affordance(voxel=(70, 50, 50)) -> np.ndarray:
    m = API.get_empty_affordance_map()
    m[voxel] = 1
    return m


def test_cost_is_minimal_at_the_target_and_grows_away_from_it() -> None:
    cmap = compose_cost_map(GRID, _affordance(), START)
    target = tuple(np.array([70, 50, 50]) // 2)
    assert cmap.cost[target] == 0
    assert cmap.cost.min() == 0
    assert np.unravel_index(np.argmin(cmap.cost), cmap.cost.shape) == target
    assert cmap.cost[0, 0, 0] == pytest.approx(2.0)  # farthest voxel: weight 2 × normalised 1
    assert (
        cmap.cost[target[0] - 10, target[1], target[2]]
        > cmap.cost[target[0] - 5, target[1], target[2]]
    )


def test_cost_is_high_near_avoided_objects() -> None:
    avoid = API.get_empty_avoidance_map()
    API.set_voxel_by_radius(avoid, (30, 50, 50), 5, 1)
    cmap = compose_cost_map(GRID, _affordance(), START, avoidance_map=avoid)
    near, far = cmap.avoidance_cost[15, 25, 25], cmap.avoidance_cost[15, 5, 25]
    assert near == pytest.approx(1.0)
    assert far < 0.05
    assert cmap.cost[15, 25, 25] > cmap.cost[15, 10, 25]


def test_obstacles_are_cleared_at_the_target_and_around_the_entity() -> None:
    occ = np.ones(GRID.shape, bool)
    cmap = compose_cost_map(GRID, _affordance(), START, occupancy=occ)
    fine = cmap.fine_obstacles
    tgt = GRID.voxel_to_world([70, 50, 50])
    near_t = GRID.world_to_voxel(tgt + [0.04, 0, 0])
    far_t = GRID.world_to_voxel(tgt + [0.07, 0, 0])
    assert not fine[tuple(near_t)] and fine[tuple(far_t)]
    near_s = GRID.world_to_voxel(START + [0, 0.04, 0])
    assert not fine[tuple(near_s)] and fine[tuple(GRID.world_to_voxel(START + [0, 0.07, 0]))]
    assert not cmap.obstacles[tuple(np.array([70, 50, 50]) // 2)]


def test_entity_occupancy_is_not_an_obstacle() -> None:
    occ = np.zeros(GRID.shape, bool)
    occ[40:45, 40:45, 0:5] = True
    ent = np.zeros_like(occ)
    ent[40:45, 40:45, 0:5] = True
    cmap = compose_cost_map(GRID, _affordance(), START, occupancy=occ, entity_occupancy=ent)
    assert not cmap.fine_obstacles.any()


def test_coarse_obstacles_are_conservative() -> None:
    occ = np.zeros(GRID.shape, bool)
    occ[41, 23, 77] = True
    cmap = compose_cost_map(GRID, _affordance(), START, occupancy=occ)
    assert cmap.obstacles[20, 11, 38]
    assert cmap.obstacles.sum() == 1


def test_pool_max_pads_odd_shapes() -> None:
    vol = np.arange(27, dtype=float).reshape(3, 3, 3)
    pooled = pool_max(vol, 2)
    assert pooled.shape == (2, 2, 2)
    assert pooled[0, 0, 0] == 13 and pooled[1, 1, 1] == 26


def test_graded_affordance_uses_its_maxima_as_targets() -> None:
    m = API.get_empty_affordance_map()
    m[10:20, 10:20, 10:20] = 0.5
    m[60, 60, 60] = 0.9
    cmap = compose_cost_map(GRID, m, START)
    assert cmap.fine_targets.tolist() == [[60, 60, 60]]
    lenient = compose_cost_map(GRID, m, START, config=CostMapConfig(target_threshold=0.5))
    assert len(lenient.fine_targets) == 1001


def test_all_zero_affordance_raises() -> None:
    with pytest.raises(EmptyAffordanceError, match="no positive voxel"):
        compose_cost_map(GRID, API.get_empty_affordance_map(), START)


def test_bad_maps_and_start_raise() -> None:
    with pytest.raises(InvalidMapError, match="shape"):
        compose_cost_map(GRID, np.ones((50, 50, 50)), START)
    bad = _affordance()
    bad[0, 0, 0] = np.inf
    with pytest.raises(InvalidMapError, match="NaN or inf"):
        compose_cost_map(GRID, bad, START)
    with pytest.raises(OutOfWorkspaceError, match=r"\[1\.5, 0\.1, 0\.1\]"):
        compose_cost_map(GRID, _affordance(), [1.5, 0.1, 0.1])
    with pytest.raises(OutOfWorkspaceError, match="occupancy"):
        compose_cost_map(GRID, _affordance(), START, occupancy=np.zeros((3, 3, 3), bool))


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("affordance_weight", 0.0),
        ("avoidance_sigma", -1.0),
        ("target_threshold", 0.0),
        ("downsample", 0),
        ("gaussian_truncate", 100.0),
        ("target_clear_radius_cm", float("nan")),
    ],
)
def test_config_rejects_bad_values(field: str, value: float) -> None:
    with pytest.raises(ConfigError, match=f"CostMapConfig.{field}"):
        CostMapConfig(**{field: value})


def test_region_of_interest_gaussian_equals_the_full_filter() -> None:
    from scipy import ndimage

    from voxposer.valuemaps.voxel_ops import smooth_zero_padded

    rng = np.random.default_rng(0)
    vol = np.zeros((50, 40, 30), np.float32)
    vol[10:20, 30:35, 5:9] = rng.random((10, 5, 4))
    full = ndimage.gaussian_filter(vol, 5, truncate=3, mode="constant")
    smoothed = smooth_zero_padded(vol, 5, 3)
    np.testing.assert_allclose(smoothed, full, rtol=0, atol=1e-6 * float(full.max()))
    assert np.array_equal(smoothed != 0, full != 0)  # zero exactly where the filter is
    assert not smooth_zero_padded(np.zeros((8, 8, 8), np.float32), 2, 3).any()


@pytest.mark.parametrize("count", [1, 3, 50])
def test_target_distance_equals_the_distance_transform(count: int) -> None:
    from scipy import ndimage

    from voxposer.valuemaps.voxel_ops import distance_to

    rng = np.random.default_rng(count)
    vox = np.unique(rng.integers(0, [50, 40, 30], size=(count, 3)), axis=0)
    mask = np.zeros((50, 40, 30), bool)
    mask[tuple(vox.T)] = True
    np.testing.assert_allclose(
        distance_to(mask, vox), ndimage.distance_transform_edt(~mask), atol=1e-4
    )


@pytest.mark.parametrize(("shape", "factor"), [((100, 100, 100), 2), ((9, 7, 5), 2), ((10, 8, 7), 3)])
def test_pool_max_is_the_block_maximum(shape, factor) -> None:
    rng = np.random.default_rng(3)
    vol = rng.normal(size=shape).astype(np.float32)
    padded_shape = tuple(-(-n // factor) * factor for n in shape)
    padded = np.full(padded_shape, vol.min(), np.float32)
    padded[: shape[0], : shape[1], : shape[2]] = vol
    a, b, c = (n // factor for n in padded_shape)
    expected = padded.reshape(a, factor, b, factor, c, factor).max(axis=(1, 3, 5))
    assert np.array_equal(pool_max(vol, factor), expected)
    assert np.array_equal(pool_max(vol > 0.5, factor), expected > 0.5)


@pytest.mark.parametrize("shape", [(100, 100, 100), (7, 1, 5), (3, 4, 0)])
def test_nonzero_voxels_is_argwhere(shape) -> None:
    from voxposer.valuemaps.voxel_ops import nonzero_voxels

    values = np.random.default_rng(2).uniform(size=shape).astype(np.float32)
    for mask in (values > 0.999, values > 2.0, values >= 0.0, values):
        got, want = nonzero_voxels(mask), np.argwhere(mask)
        assert got.dtype == want.dtype and got.shape == want.shape
        np.testing.assert_array_equal(got, want)


def test_keep_out_from_the_pooled_map_equals_pooling_the_core() -> None:
    rng = np.random.default_rng(4)
    avoid = rng.random(GRID.shape).astype(np.float32) ** 4
    for start in (START, np.array([0.5, 0.5, 0.5])):
        fine_core = avoid >= 0.5 * avoid.max()
        direct = keep_out(GRID, avoid, start, 0.5, 2)
        assert np.array_equal(direct, keep_out(GRID, avoid, start, 0.5, 2, pool_max(avoid, 2)))
        if avoid[tuple(GRID.world_to_voxel(start))] < 0.5 * avoid.max():
            assert np.array_equal(direct, pool_max(fine_core, 2))


def test_the_soft_fallback_map_equals_composing_without_the_core() -> None:
    avoid = API.get_empty_avoidance_map()
    API.set_voxel_by_radius(avoid, [50, 50, 50], 15, 1.0)
    occ = np.zeros(GRID.shape, bool)
    occ[40:44, 20:80, 20:80] = True
    cmap = compose_cost_map(GRID, _affordance(), START, avoid, occ)
    soft = compose_cost_map(GRID, _affordance(), START, avoid, occ,
                            config=CostMapConfig(avoidance_keep_out=0.0))
    fallback = without_keep_out(cmap)
    assert cmap.obstacles.sum() > soft.obstacles.sum()  # the core was an obstacle
    assert np.array_equal(fallback.obstacles, soft.obstacles)
    assert np.array_equal(fallback.cost, soft.cost)
    assert fallback.config == soft.config


def test_off_limits_voxels_are_obstacles_cleared_at_the_start_and_kept_by_the_fallback() -> None:
    grid = VoxelGrid((0, 0, 0), (1, 1, 1), (40, 40, 40))
    aff = np.zeros(grid.shape, dtype=np.float32)
    aff[35, 20, 20] = 1.0
    start = grid.voxel_to_world([5, 20, 20])
    off = np.zeros(grid.shape, dtype=bool)
    off[:10] = True  # the start's side, start included
    off[20] = True  # a wall across the way
    cmap = compose_cost_map(grid, aff, start, off_limits=off)
    coarse = cmap.grid.world_to_voxel
    assert cmap.obstacles[tuple(coarse(grid.voxel_to_world([20, 5, 30])))]
    assert not cmap.obstacles[tuple(coarse(start))], "cleared around the start"
    assert cmap.obstacles[tuple(coarse(grid.voxel_to_world([1, 35, 5])))]
    plain = compose_cost_map(grid, aff, start)
    assert not plain.obstacles.any()
    again = without_keep_out(cmap)
    np.testing.assert_array_equal(again.obstacles, cmap.obstacles)
    with pytest.raises(OutOfWorkspaceError, match=r"off_limits has shape \(3, 3\)"):
        compose_cost_map(grid, aff, start, off_limits=np.zeros((3, 3), dtype=bool))
