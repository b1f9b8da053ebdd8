"""Pushing a sliding part (a drawer's handle) closed in the MuJoCo world: the hand's pose for it,
and a low drawer with noisy depth (hand-written map programs, no LLM)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from voxposer.control import ClosedLoopController
from voxposer.control.pushing_loop import side_push_quat
from voxposer.envs import TabletopWorld
from voxposer.envs.layout import SceneLayout
from voxposer.pipeline import simulated_perceiver
from voxposer.valuemaps import ValueMapAPI


@pytest.mark.parametrize("angle", [np.pi / 2, 0.0, -2.0])
def test_the_hand_points_along_the_push_with_its_fingers_level(angle: float) -> None:
    direction = np.array([np.cos(angle), np.sin(angle), 0.0])
    hand = Rotation.from_quat(side_push_quat(direction))
    np.testing.assert_allclose(hand.apply([0, 0, 1]), direction, atol=1e-9)  # approach axis
    assert abs(hand.apply([1.0, 0, 0])[2]) < 1e-9  # the long (finger) axis lies level


@pytest.mark.parametrize("perception", ["ground-truth", "ground-truth-noisy"])
def test_the_bottom_drawer_is_pushed_shut_at_its_handle_height(
    world: TabletopWorld, perception: str
) -> None:
    """Its handle is ~7 cm up. An upright hand stopped ~3.5 cm above every push target and moved
    the drawer ~1 cm a push (it crept shut on the exact cloud only), and with noisy depth the
    cabinet's unlabelled edge points around the handle turned its path and pushes outwards."""
    layout = SceneLayout(blocks=("blue",), drawer_openings={"bottom": 0.15}, extra_blocks=(0, 0))
    world.reset(np.random.default_rng(2), layout)
    perceiver = simulated_perceiver(world, perception, seed=3)
    grid = world.grid
    api = ValueMapAPI(grid, lambda: world.get_ee_pose()[1], world.get_gripper_state)
    start = perceiver.detect("bottom drawer handle").position
    target = start - 0.25 * world.drawer_axis("bottom drawer")  # 25 cm into the cabinet
    assert target[1] > start[1]

    def affordance() -> np.ndarray:
        m = api.get_empty_affordance_map()
        m[tuple(grid.world_to_voxel(target))] = 1
        return m

    heights: list[float] = []
    world.step_callbacks.append(lambda w: heights.append(float(w.get_ee_pose()[0][2])))
    try:
        result = ClosedLoopController(world, perceiver, np.random.default_rng(2))(
            lambda: perceiver.detect("bottom drawer handle"), affordance
        )
    finally:
        world.step_callbacks.pop()
    assert world.drawer_opening("bottom") < 0.02, result.message
    assert min(heights) < start[2] + 0.02  # down at the handle
    first_push = result.entity_path[1] - result.entity_path[0]
    assert first_push[1] > 0.04  # into the cabinet, most of a push's 1-8 cm
