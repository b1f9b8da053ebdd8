import numpy as np
import pytest
from numpy.typing import NDArray

from voxposer.errors import ConfigError, PlanningError
from voxposer.planning.dynamics import PushBatch, PushPrediction, translate_points
from voxposer.planning.mpc import random_shooting
from voxposer.planning.push_primitive import PushAction, PushConfig, push_waypoints
from voxposer.planning.synthetic_scene import box_surface_points
from voxposer.valuemaps import ValueMapAPI, VoxelGrid, compose_cost_map

BLOCK = box_surface_points(np.array([0.475, 0.475, 0.0]), np.array([0.525, 0.525, 0.05]))
CENTRE = BLOCK.mean(axis=0)


def test_dynamics_translates_every_point_along_the_push() -> None:
    dirs = np.array([[1.0, 0, 0], [0, -1.0, 0]])
    moved = translate_points(BLOCK, dirs, np.array([0.05, 0.02]))
    assert moved.shape == (2, len(BLOCK), 3)
    np.testing.assert_allclose(moved[0] - BLOCK, np.tile([0.05, 0, 0], (len(BLOCK), 1)))
    np.testing.assert_allclose(moved[1] - BLOCK, np.tile([0, -0.02, 0], (len(BLOCK), 1)))


@pytest.mark.parametrize("heading", [0.0, np.pi / 2, 2.5, -2.0])
def test_mpc_pushes_towards_the_path_and_contacts_the_rear_face(heading: float) -> None:
    u = np.array([np.cos(heading), np.sin(heading), 0.0])
    path = CENTRE + np.linspace(0, 0.3, 31)[:, None] * u
    action = random_shooting(BLOCK, path, np.random.default_rng(0))
    assert action.direction @ u > 0.99
    assert action.distance == pytest.approx(0.06, abs=0.01)  # the look-ahead
    assert np.linalg.norm(action.predicted_position - (CENTRE + 0.06 * u)) < 0.01
    # contact on the face opposite the push, at push height
    rear = CENTRE - u * (0.025 / max(abs(u[0]), abs(u[1])))
    assert np.linalg.norm(action.contact[:2] - rear[:2]) < 0.03
    assert action.contact[2] == pytest.approx(PushConfig().contact_height_m)


def test_mpc_respects_a_sliding_axis() -> None:
    path = CENTRE + np.linspace(0, 0.2, 21)[:, None] * np.array([0.7, 0.7, 0])
    action = random_shooting(BLOCK, path, np.random.default_rng(1), axis=np.array([1.0, 0, 0]))
    np.testing.assert_allclose(action.direction, [1, 0, 0])


def test_mpc_avoids_pushing_into_obstacles() -> None:
    grid = VoxelGrid((0, 0, 0), (1, 1, 1))
    api = ValueMapAPI(grid)
    aff = api.get_empty_affordance_map()
    aff[tuple(grid.world_to_voxel([0.8, 0.5, 0.025]))] = 1
    wall = box_surface_points(np.array([0.56, 0.40, 0.0]), np.array([0.58, 0.60, 0.1]))
    cmap = compose_cost_map(grid, aff, CENTRE, occupancy=grid.points_to_occupancy(wall))
    straight = CENTRE + np.linspace(0, 0.3, 31)[:, None] * np.array([1.0, 0, 0])
    free = random_shooting(BLOCK, straight, np.random.default_rng(2))
    blocked = random_shooting(BLOCK, straight, np.random.default_rng(2), cost_map=cmap)
    assert free.distance > 0.05
    moved_front = blocked.predicted_position[0] + 0.025
    assert moved_front < 0.565  # stops short of the wall rather than pushing into it


def test_push_waypoints_approach_from_behind_and_follow_through() -> None:
    path = CENTRE + np.linspace(0, 0.3, 31)[:, None] * np.array([1.0, 0, 0])
    action = random_shooting(BLOCK, path, np.random.default_rng(3))
    wps = push_waypoints(action)
    assert wps.shape == (5, 3)
    assert wps[1][0] < action.contact[0] - 0.04  # starts behind the contact point
    assert wps[2][0] == pytest.approx(action.contact[0] + action.distance - 0.01, abs=0.01)
    assert wps[0][2] > wps[1][2] and wps[4][2] > wps[3][2]  # lowers in, lifts out


def test_bad_push_input() -> None:
    with pytest.raises(PlanningError, match="no observed points"):
        random_shooting(np.zeros((0, 3)), np.zeros((2, 3)), np.random.default_rng(0))
    with pytest.raises(ConfigError, match="min_distance_m"):
        PushConfig(min_distance_m=0.2, max_distance_m=0.1)


def _straight_push_with_obstacle(obstacle: NDArray[np.float64] | None) -> PushAction:
    grid = VoxelGrid((0, 0, 0), (1, 1, 1))
    aff = ValueMapAPI(grid).get_empty_affordance_map()
    aff[tuple(grid.world_to_voxel([0.8, 0.5, 0.025]))] = 1
    occ = None if obstacle is None else grid.points_to_occupancy(obstacle)
    cmap = compose_cost_map(grid, aff, CENTRE, occupancy=occ)
    straight = CENTRE + np.linspace(0, 0.3, 31)[:, None] * np.array([1.0, 0, 0])
    return random_shooting(BLOCK, straight, np.random.default_rng(4), cost_map=cmap)


def test_hand_lies_across_the_push_unless_that_sweeps_it_through_an_obstacle() -> None:
    free = _straight_push_with_obstacle(None)
    assert abs(free.hand_axis @ free.direction) < 0.2  # flat contact: fingers across the push
    # a 3 cm box 9 cm beside the push: the hand's underside (≈ 5.2 cm high) passes above it
    low = box_surface_points(np.array([0.525, 0.565, 0.0]), np.array([0.575, 0.615, 0.03]))
    assert abs(_straight_push_with_obstacle(low).hand_axis[0]) < 0.2
    # a 12 cm box there: the hand (±10.5 cm along its finger axis) would sweep through it, so it
    # turns along the push instead
    tall = box_surface_points(np.array([0.525, 0.565, 0.0]), np.array([0.575, 0.615, 0.12]))
    turned = _straight_push_with_obstacle(tall)
    assert turned.direction[0] > 0.9
    assert abs(turned.hand_axis @ turned.direction) > 0.8


def test_lazy_hand_sweep_penalty_picks_the_same_push_as_penalising_every_sample() -> None:
    from voxposer.planning.push_clearance import add_hand_sweep

    grid = VoxelGrid((0, 0, 0), (1, 1, 1))
    aff = ValueMapAPI(grid).get_empty_affordance_map()
    aff[tuple(grid.world_to_voxel([0.8, 0.5, 0.025]))] = 1
    wall = box_surface_points(np.array([0.46, 0.56, 0.0]), np.array([0.62, 0.58, 0.1]))
    cmap = compose_cost_map(grid, aff, CENTRE, occupancy=grid.points_to_occupancy(wall))
    rng = np.random.default_rng(4)
    n = 2000
    theta = rng.uniform(-np.pi, np.pi, n)
    dirs = np.stack([np.cos(theta), np.sin(theta), np.zeros(n)], axis=1)
    side = np.stack([-dirs[:, 1], dirs[:, 0], np.zeros(n)], axis=1)
    contacts = CENTRE - 0.025 * dirs
    dist = rng.uniform(0.01, 0.08, n)
    score = rng.uniform(0, 0.1, n)
    cfg = PushConfig()
    lazy, lazy_along = add_hand_sweep(score, contacts, dirs, dist, side, cmap, cfg, first=16)
    full, full_along = add_hand_sweep(score, contacts, dirs, dist, side, cmap, cfg, first=n)
    assert np.argmin(lazy) == np.argmin(full) and lazy.min() == full.min()
    assert lazy_along[np.argmin(lazy)] == full_along[np.argmin(full)]


class _Reversed:
    """A test double of a dynamics model: the object moves against the push."""

    def predict(self, centre, points, pushes: PushBatch) -> PushPrediction:
        step = -pushes.directions * pushes.distances[:, None]
        return PushPrediction(centre + step, points[None] + step[:, None, :])


def test_the_mpc_chooses_through_the_dynamics_model_it_is_given() -> None:
    """With a model in which objects move against the push, the best push points away from
    the goal; with the paper's heuristic it points toward it."""
    path = np.array([[0.5, 0.5, 0.025], [0.7, 0.5, 0.025]])
    heuristic = random_shooting(BLOCK, path, np.random.default_rng(4))
    reversed_ = random_shooting(BLOCK, path, np.random.default_rng(4), model=_Reversed())
    assert heuristic.direction[0] > 0.95
    assert reversed_.direction[0] < -0.95
    assert reversed_.predicted_position[0] > 0.5  # predicted by the model: toward the goal


def test_a_push_the_arm_could_not_reach_is_not_chosen_again() -> None:
    """The arm refused the best push (unreachable): the next choice, with or without a cost map
    (whose hand-sweep penalty is computed for the best samples only), lies outside the refused
    cone and still moves the block forward."""
    grid = VoxelGrid((0, 0, 0), (1, 1, 1))
    aff = ValueMapAPI(grid).get_empty_affordance_map()
    aff[tuple(grid.world_to_voxel([0.8, 0.5, 0.025]))] = 1
    cmap = compose_cost_map(grid, aff, CENTRE)
    straight = CENTRE + np.linspace(0, 0.3, 31)[:, None] * np.array([1.0, 0, 0])
    for cost_map in (None, cmap):
        first = random_shooting(BLOCK, straight, np.random.default_rng(5), cost_map=cost_map)
        assert first.direction @ [1.0, 0, 0] > 0.99
        again = random_shooting(BLOCK, straight, np.random.default_rng(5), cost_map=cost_map,
                                refused=first.direction[None])
        assert again.direction @ first.direction < np.cos(np.radians(30.0))
        assert again.predicted_position[0] > CENTRE[0] + 0.01
        assert again.score < 1.0


def test_when_every_push_was_refused_the_best_is_still_chosen() -> None:
    path = CENTRE + np.linspace(0, 0.2, 21)[:, None] * np.array([1.0, 0, 0])
    both = np.array([[1.0, 0, 0], [-1.0, 0, 0]])
    action = random_shooting(BLOCK, path, np.random.default_rng(1), axis=np.array([1.0, 0, 0]),
                             refused=both)
    np.testing.assert_allclose(action.direction, [1, 0, 0])


def test_a_bad_refusal_angle_is_refused_naming_it() -> None:
    with pytest.raises(ConfigError, match=r"refused_angle_deg.*\[0, 180\].*200"):
        PushConfig(refused_angle_deg=200.0)
