"""The stage-wise value-map cost and the recorded zero-shot trajectory."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from voxposer.errors import ConfigError
from voxposer.learning.state import LAYOUTS
from voxposer.learning.task_cost import TaskCost, TaskCostConfig
from voxposer.learning.zero_shot import ZeroShotTrajectory, load_trajectories

from .toy_door import HANDLE, trajectory


def _obs(ee: np.ndarray, handle: np.ndarray) -> np.ndarray:
    return np.r_[ee, 0.0, handle, 0.0, 0.0]


def test_stage_advances_only_when_its_entity_reaches_the_target() -> None:
    cost = TaskCost(trajectory().stages, LAYOUTS["door"])
    far = _obs(np.array([0.0, 0.0, 0.3]), HANDLE)
    at_handle = _obs(HANDLE + [0.005, 0, 0], HANDLE)
    assert cost.advance(far, 0) == 0
    assert cost.advance(at_handle, 0) == 1
    # the last stage's entity is the handle: the hand near its target does not end it
    assert cost.advance(_obs(HANDLE - [0.2, 0, 0], HANDLE), 1) == 1
    assert cost.remaining(_obs(HANDLE, HANDLE - [0.2, 0, 0]), 1) < 0.02


def test_cost_ranks_samples_by_the_stage_entity() -> None:
    cost = TaskCost(trajectory().stages, LAYOUTS["door"], TaskCostConfig(prior_weight=0.0))
    pulled = _obs(HANDLE - [0.1, 0, 0], HANDLE - [0.1, 0, 0])
    stuck = _obs(HANDLE - [0.1, 0, 0], HANDLE)  # the hand moved, the handle did not
    predicted = np.stack([np.tile(pulled, (3, 1)), np.tile(stuck, (3, 1))])
    c = cost(predicted, np.zeros((2, 3, 4)), stage=1)
    assert c.shape == (2,) and c[0] < c[1]
    # in stage 0 (entity: the hand) both are equally far from the handle
    c0 = cost(predicted, np.zeros((2, 3, 4)), stage=0)
    assert c0[0] == pytest.approx(c0[1])


def test_prior_term_prefers_samples_near_the_prior_targets() -> None:
    cost = TaskCost(trajectory().stages, LAYOUTS["door"])
    near, off = _obs(HANDLE, HANDLE), _obs(HANDLE + [0, 0.05, 0], HANDLE)
    predicted = np.stack([np.tile(near, (2, 1)), np.tile(off, (2, 1))])
    c = cost(predicted, np.zeros((2, 2, 4)), 1, prior_targets=np.tile(HANDLE, (2, 1)))
    assert c[0] < c[1]


def test_bad_weights_and_entities_are_refused() -> None:
    with pytest.raises(ConfigError, match="reach_m"):
        TaskCostConfig(reach_m=-1)
    with pytest.raises(ConfigError, match=r"'cup'.*observed: gripper, door handle, door"):
        LAYOUTS["door"].entity_slice("cup")


def test_zero_shot_round_trip_and_prior_actions(tmp_path: Path) -> None:
    traj = trajectory(seed=3)
    path = traj.save(tmp_path)
    back = ZeroShotTrajectory.load(path)
    assert path.name == "toy-3.npz"
    np.testing.assert_array_equal(back.waypoints, traj.waypoints)
    np.testing.assert_array_equal(back.stages[1].cost, traj.stages[1].cost)
    assert back.stages[1].entity == "door handle" and back.stages[0].grid == traj.stages[0].grid
    acts = back.prior_actions
    assert acts.shape == (len(traj.waypoints) - 1, 4)
    np.testing.assert_allclose(traj.waypoints[0] + acts[:, :3].sum(axis=0), traj.waypoints[-1])
    assert load_trajectories(tmp_path, "door")[0].seed == 3
    with pytest.raises(ConfigError, match="no zero-shot trajectory of task 'fridge'"):
        load_trajectories(tmp_path, "fridge")


def test_malformed_trajectory_is_refused() -> None:
    t = trajectory()
    with pytest.raises(ConfigError, match="gripper has 3 rows"):
        ZeroShotTrajectory(t.task, t.source, 0, t.waypoints, t.quats, t.gripper[:3],
                           t.stage_of, 0.25, False, t.stages)


def test_anchored_prior_and_cost_follow_a_displaced_object(tmp_path: Path) -> None:
    """A reset that moves the object 3 cm: τ₀'s targets and the maps move with the observed
    handle; a τ₀ recorded without the handle's start is not re-anchored."""
    from dataclasses import replace

    from voxposer.learning.policies import LearningPolicy, stage_orientations
    from voxposer.planning.waypoint_mpc import WaypointMPCConfig

    traj = replace(trajectory(), handle_start=HANDLE.copy())
    assert ZeroShotTrajectory.load(traj.save(tmp_path)).handle_start == pytest.approx(HANDLE)
    mpc = WaypointMPCConfig((-0.03,) * 3 + (0.0,), (0.03,) * 3 + (1.0,), n_samples=4, horizon=3)
    shift = np.array([0.03, -0.02, 0.0])
    o0 = _obs(traj.waypoints[0] + shift, HANDLE + shift)
    for prior in (traj, None):
        cost = TaskCost(traj.stages, LAYOUTS["door"])
        policy = LearningPolicy(cost, mpc, prior, stage_orientations(traj),
                                anchor_handle=traj.handle_start)
        policy.act(o0, 0, 0, np.random.default_rng(0))
        np.testing.assert_allclose(cost.shift, shift)
        # the reach stage is done where the displaced handle is, not where τ₀ saw it
        assert cost.remaining(_obs(HANDLE + shift, HANDLE + shift), 0) < 0.02  # 2 cm voxels
        assert cost.remaining(_obs(HANDLE, HANDLE + shift), 0) > 0.03
    _, targets = policy_with_prior(traj, mpc, o0)
    np.testing.assert_allclose(targets[0], traj.waypoints[1] + shift)
    plain = TaskCost(traj.stages, LAYOUTS["door"])
    LearningPolicy(plain, mpc, trajectory(), stage_orientations(traj)).act(
        o0, 0, 0, np.random.default_rng(0))
    np.testing.assert_array_equal(plain.shift, np.zeros(3))


def policy_with_prior(traj: ZeroShotTrajectory, mpc: object, o0: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    from voxposer.learning.policies import LearningPolicy, stage_orientations

    policy = LearningPolicy(TaskCost(traj.stages, LAYOUTS["door"]), mpc,  # type: ignore[arg-type]
                            traj, stage_orientations(traj))
    policy.anchor(o0)
    return policy.prior_window(o0, 0)


def test_with_a_prior_the_hand_holds_tau0s_own_orientation() -> None:
    from dataclasses import replace

    from scipy.spatial.transform import Rotation

    from voxposer.learning.policies import LearningPolicy, stage_orientations
    from voxposer.planning.waypoint_mpc import WaypointMPCConfig

    base = trajectory()
    turning = Rotation.from_euler("z", np.linspace(0, 40, len(base.waypoints))[:, None], degrees=True)
    traj = replace(base, quats=turning.as_quat())
    mpc = WaypointMPCConfig((-0.03,) * 3 + (0.0,), (0.03,) * 3 + (1.0,), n_samples=4, horizon=3)
    with_prior = LearningPolicy(TaskCost(traj.stages, LAYOUTS["door"]), mpc, traj,
                                stage_orientations(traj))
    without = LearningPolicy(TaskCost(traj.stages, LAYOUTS["door"]), mpc, None,
                             stage_orientations(traj))
    for step in (0, 5, 12):
        np.testing.assert_allclose(with_prior.orientation(step, 1), traj.quats[step + 1])
    # without a prior: the orientation at the end of the stage, whatever the step
    np.testing.assert_allclose(without.orientation(0, 1), traj.quats[-1])
    np.testing.assert_allclose(without.orientation(12, 1), traj.quats[-1])


def test_on_an_opened_hinge_the_hand_keeps_facing_the_part() -> None:
    """The rotation map is re-read on the part as observed: a door 30° open that τ₀'s hand never
    turned with turns the hand 30° about z; a door as far open as τ₀'s hand had turned leaves
    τ₀'s orientation; during the grasp (stage 0) nothing is turned."""
    from dataclasses import replace

    from scipy.spatial.transform import Rotation

    from voxposer.learning.policies import LearningPolicy, hand_turns, stage_orientations
    from voxposer.planning.waypoint_mpc import WaypointMPCConfig

    mpc = WaypointMPCConfig((-0.03,) * 3 + (0.0,), (0.03,) * 3 + (1.0,), n_samples=4, horizon=3)
    still = trajectory()
    opened = np.r_[HANDLE, 0.0, HANDLE, 0.0, np.radians(30.0)]
    step = len(still.waypoints) - 3
    policy = LearningPolicy(TaskCost(still.stages, LAYOUTS["door"]), mpc, still,
                            stage_orientations(still))
    turned = Rotation.from_quat(policy.orientation(step, 1, opened))
    held = Rotation.from_quat(still.quats[step + 1])
    assert np.degrees((turned * held.inv()).as_rotvec()[2]) == pytest.approx(30.0, abs=1e-6)
    np.testing.assert_allclose(policy.orientation(step, 0, opened), still.quats[step + 1])
    # a τ₀ whose hand turned 30° with the door after its grasp: nothing more to turn
    first = int(np.flatnonzero(still.stage_of > 0)[0])
    yaw = np.where(np.arange(len(still.waypoints)) >= first,
                   np.linspace(0, 30, len(still.waypoints)) - np.linspace(0, 30, len(
                       still.waypoints))[first - 1], 0.0)
    yaw[-4:] = 30.0
    rot = Rotation.from_euler("z", yaw[:, None], degrees=True) * Rotation.from_quat(
        still.quats[first - 1])
    turning = replace(still, quats=rot.as_quat())
    assert hand_turns(turning)[step + 1] == pytest.approx(np.radians(30.0), abs=1e-6)
    follower = LearningPolicy(TaskCost(turning.stages, LAYOUTS["door"]), mpc, turning,
                              stage_orientations(turning))
    np.testing.assert_allclose(np.abs(follower.orientation(step, 1, opened) @ turning.quats[
        step + 1]), 1.0, atol=1e-9)
