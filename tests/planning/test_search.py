"""The path search's shortcuts for unreachable targets give the answer the full search gives."""

import numpy as np
import pytest
from scipy import ndimage

from voxposer.planning import astar, search
from voxposer.planning.search_kernel import near_blocked, sealed_off

SHAPE = (30, 30, 30)


def _box(centre: tuple[int, int, int], half: int, open_side: bool = False) -> np.ndarray:
    """Blocked walls of a cube around ``centre`` (one face missing with ``open_side``)."""
    blocked = np.zeros(SHAPE, bool)
    c, h = np.array(centre), half
    lo, hi = c - h, c + h + 1
    blocked[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]] = True
    blocked[lo[0] + 1:hi[0] - 1, lo[1] + 1:hi[1] - 1, lo[2] + 1:hi[2] - 1] = False
    if open_side:
        blocked[lo[0], lo[1] + 1:hi[1] - 1, lo[2] + 1:hi[2] - 1] = False
    return blocked


def _search(blocked: np.ndarray, target: tuple[int, int, int], start=(2, 2, 2), **kw):
    mask = np.zeros(SHAPE, bool)
    mask[target] = True
    dist = ndimage.distance_transform_edt(~mask).astype(np.float32)
    return astar(np.zeros(SHAPE, np.float32), blocked, mask, dist, np.array(start),
                 length_weight=0.1, affordance_scale=0.0, **kw)


def test_a_sealed_box_is_proved_sealed_and_an_open_one_is_not() -> None:
    target = np.zeros(SHAPE, bool)
    target[20, 20, 20] = True
    start = np.array([2, 2, 2])
    assert sealed_off(_box((20, 20, 20), 4), target, start, 4096)
    assert not sealed_off(_box((20, 20, 20), 4, open_side=True), target, start, 4096)
    assert not sealed_off(_box((20, 20, 20), 4), target, start, 100)  # too big to tell
    assert not sealed_off(_box((20, 20, 20), 4), target, np.array([19, 20, 20]), 4096)


def test_a_sealed_target_reports_the_reachable_voxels_and_the_nearest_of_them(monkeypatch
                                                                              ) -> None:
    blocked = _box((20, 20, 20), 4)
    fast = _search(blocked, (20, 20, 20))
    monkeypatch.setattr(search, "SEALED_BUDGET", 0)  # no shortcut: A* expands all it reaches
    monkeypatch.setattr(search, "CONNECTIVITY_AFTER", 10 ** 9)
    full = _search(blocked, (20, 20, 20))
    assert len(fast.path) == 0 and not np.isfinite(fast.cost)
    assert len(full.path) == 0
    free = (~blocked).sum() - 7 ** 3  # everything outside the box
    assert fast.expanded == full.expanded == free
    d = np.linalg.norm(fast.closest - 20)
    assert d == pytest.approx(np.linalg.norm(full.closest - 20))
    assert d == pytest.approx(5.0)  # just outside a wall, level with the target


def test_a_wall_across_the_grid_is_found_by_the_connectivity_check(monkeypatch) -> None:
    blocked = np.zeros(SHAPE, bool)
    blocked[15, :, :] = True  # both sides are far bigger than the sealed-off budget
    monkeypatch.setattr(search, "SEALED_BUDGET", 64)
    monkeypatch.setattr(search, "CONNECTIVITY_AFTER", 500)
    result = _search(blocked, (25, 15, 15))
    assert len(result.path) == 0
    assert result.expanded == 15 * 30 * 30  # the start's side
    assert result.closest[0] == 14


def test_a_reachable_target_beyond_the_check_gives_the_same_path(monkeypatch) -> None:
    blocked = np.zeros(SHAPE, bool)
    blocked[15, :, :] = True
    blocked[15, 27, 27] = False  # a one-voxel hole in a far corner
    plain = _search(blocked, (25, 15, 15))
    monkeypatch.setattr(search, "CONNECTIVITY_AFTER", 300)
    checked = _search(blocked, (25, 15, 15))
    assert checked.cost == pytest.approx(plain.cost)
    assert np.array_equal(checked.path, plain.path)
    assert tuple(checked.path[-1]) == (25, 15, 15)
    assert any(tuple(p) == (15, 27, 27) for p in checked.path)


def test_near_blocked_is_the_3x3x3_neighbourhood_of_blocked_voxels() -> None:
    rng = np.random.default_rng(2)
    blocked = rng.random(SHAPE) < 0.01
    expected = ndimage.binary_dilation(blocked, structure=np.ones((3, 3, 3), bool))
    assert np.array_equal(near_blocked(blocked), expected)


def _dijkstra_cost(cost: np.ndarray, blocked: np.ndarray, target: tuple[int, int, int],
                   start: tuple[int, int, int], length_weight: float) -> float:
    """The lowest path cost by Dijkstra (scipy.sparse.csgraph) over the moves the search allows:
    26-connected, into free voxels, cutting no corner, each costing ``|step| * (w + cost[v])``."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    shape = cost.shape
    index = np.arange(cost.size).reshape(shape)
    rows, cols, weights = [], [], []
    for u in np.argwhere(~blocked):
        for step in np.argwhere(np.ones((3, 3, 3), bool)) - 1:
            v = u + step
            if not step.any() or np.any(v < 0) or np.any(v >= shape) or blocked[tuple(v)]:
                continue
            lo, hi = np.minimum(u, v), np.maximum(u, v) + 1
            box = blocked[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]]
            if box.any():  # u is free, so any blocked voxel of the box is a cut corner
                continue
            rows.append(index[tuple(u)])
            cols.append(index[tuple(v)])
            weights.append(np.linalg.norm(step) * (length_weight + cost[tuple(v)]))
    graph = coo_matrix((weights, (rows, cols)), shape=(cost.size, cost.size)).tocsr()
    return float(dijkstra(graph, indices=index[start])[index[target]])


@pytest.mark.parametrize("seed", range(4))
def test_the_search_finds_the_lowest_cost_path_on_an_affordance_cost(seed: int) -> None:
    """With the planner's affordance term (2 d / d_max) plus a random avoidance cost, A* (whose
    heuristic must never overestimate) pays exactly what Dijkstra's full search pays."""
    rng = np.random.default_rng(seed)
    shape = (11, 11, 11)
    target, start = (8, 7, 8), (1, 2, 1)
    mask = np.zeros(shape, bool)
    mask[target] = True
    dist = ndimage.distance_transform_edt(~mask).astype(np.float32)
    blocked = rng.random(shape) < 0.2
    blocked[target] = blocked[start] = False
    cost = (2.0 * dist / dist.max() + rng.random(shape) * 0.5).astype(np.float32)
    found = astar(cost, blocked, mask, dist, np.array(start), length_weight=0.1,
                  affordance_scale=2.0 / float(dist.max()))
    expected = _dijkstra_cost(cost, blocked, target, start, 0.1)
    assert np.isfinite(expected)
    assert found.cost == pytest.approx(expected, rel=1e-6)
