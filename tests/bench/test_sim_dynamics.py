"""The simulator as the dynamics model: pushes simulated in a private copy of the world."""

import numpy as np
import pytest

from voxposer.bench.sim_dynamics import SimulatedPush
from voxposer.envs import SceneLayout, TabletopWorld
from voxposer.errors import PlanningError
from voxposer.planning.dynamics import DynamicsModel, PushBatch

HALF = 0.025  # half the block's edge [m]
X, Y = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])


@pytest.fixture(scope="module")
def scene(world: TabletopWorld) -> tuple[TabletopWorld, SimulatedPush, np.ndarray, np.ndarray]:
    """The blue block alone at the table's origin, the model, its centre and corner points."""
    world.reset(np.random.default_rng(0), SceneLayout(
        poses={"blue block": (0.0, 0.0, 0.0)}, extra_blocks=(0, 0), extra_lines=(0, 0),
        cabinet=False))
    centre = world.object_position("blue block")
    corners = centre + np.array([[sx, sy, 0.0] for sx in (-HALF, HALF) for sy in (-HALF, HALF)])
    return world, SimulatedPush(world), centre, corners


def _push(centre: np.ndarray, directions: list[np.ndarray], lateral: float = 0.0,
          distance: float = 0.06) -> PushBatch:
    """Pushes from the middle of the block's rear face (shifted ``lateral`` [m] to the left of
    each direction), at half the block's height."""
    d = np.array(directions, dtype=np.float64)
    left = np.cross([0.0, 0.0, 1.0], d)
    contacts = centre - d * HALF + left * lateral
    contacts[:, 2] = HALF
    return PushBatch(contacts, d, np.full(len(d), distance))


def test_is_a_dynamics_model(scene) -> None:
    _, model, _, _ = scene
    assert isinstance(model, SimulatedPush)
    _typed: DynamicsModel = model  # mypy checks the protocol


def test_push_through_the_centre_moves_the_block_the_push_distance(scene) -> None:
    _, model, centre, corners = scene
    pred = model.predict(centre, corners, _push(centre, [X]))
    moved = pred.centres[0] - centre
    assert 0.04 < moved @ X < 0.07
    assert abs(moved @ Y) < 0.015
    np.testing.assert_allclose(pred.points[0] - corners, np.tile(moved, (4, 1)), atol=0.005)


def test_push_that_misses_leaves_the_block_where_it_is(scene) -> None:
    _, model, centre, corners = scene
    pred = model.predict(centre, corners, _push(centre, [X], lateral=0.15))
    assert np.linalg.norm(pred.centres[0] - centre) < 0.005
    np.testing.assert_allclose(pred.points[0], corners, atol=0.005)


def test_push_at_the_edge_turns_the_block(scene) -> None:
    _, model, centre, corners = scene
    pred = model.predict(centre, corners, _push(centre, [X], lateral=0.05))
    edge = pred.points[0, 2] - pred.points[0, 0]  # was along +x
    assert abs(np.degrees(np.arctan2(edge[1], edge[0]))) > 5.0
    # a rigid motion: the block's edges keep their length
    np.testing.assert_allclose(np.linalg.norm(edge), 2 * HALF, atol=1e-6)


def test_live_world_is_untouched(scene) -> None:
    world, model, centre, corners = scene
    qpos, qvel, t = world.data.qpos.copy(), world.data.qvel.copy(), world.data.time
    model.predict(centre, corners, _push(centre, [X, -Y]))
    np.testing.assert_array_equal(world.data.qpos, qpos)
    np.testing.assert_array_equal(world.data.qvel, qvel)
    assert world.data.time == t


def test_batched_pushes_each_go_their_own_way(scene) -> None:
    _, model, centre, corners = scene
    directions = [X, Y, -Y]
    pred = model.predict(centre, corners, _push(centre, directions, distance=0.04))
    assert pred.centres.shape == (3, 3) and pred.points.shape == (3, 4, 3)
    for s, d in enumerate(directions):
        assert (pred.centres[s] - centre) @ d > 0.02
    gaps = np.linalg.norm(pred.centres[:, None] - pred.centres[None], axis=2)
    assert gaps[np.triu_indices(3, 1)].min() > 0.02


def test_bad_input_is_refused(scene) -> None:
    world, model, centre, corners = scene
    with pytest.raises(PlanningError, match="object"):
        SimulatedPush(object())
    with pytest.raises(PlanningError, match="speed_m_s"):
        SimulatedPush(world, speed_m_s=0.0)
    far = centre + np.array([0.0, 0.3, 0.0])
    with pytest.raises(PlanningError, match=r"no free body within 0.1 m .*blue_block"):
        model.predict(far, corners, _push(far, [X]))
