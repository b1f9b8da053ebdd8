"""How actions are chosen while learning: MPC through the current model, sampling around τ₀
("with prior") or uniformly over the action space ("without prior").

Before the first model is trained there is nothing to roll out: the "with prior" policy then
follows τ₀ with noise ε ~ N(0, σ²) on each waypoint, the "without prior" one acts uniformly at
random. The end-effector's orientation is τ₀'s at the waypoint an action heads for (with
prior), or the zero-shot run's at the end of the current stage (without). On a hinged part it
is also turned about the hinge (z) by how far the observed part has opened beyond what τ₀'s own
hand turned since its grasp: the zero-shot rotation map ("face the handle") is re-read on the
part as it is now, as the closed-loop executor replans it, so a hand pulling a door keeps facing
the door instead of twisting the bar in its fingers.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from voxposer.errors import ConfigError
from voxposer.learning.task_cost import TaskCost
from voxposer.learning.zero_shot import ZeroShotTrajectory
from voxposer.planning.dynamics.state_model import StateDynamicsModel
from voxposer.planning.waypoint_mpc import WaypointMPCConfig, plan_action, sample_action_sequences


def stage_orientations(trajectory: ZeroShotTrajectory) -> NDArray[np.float64]:
    """The end-effector orientation (x, y, z, w) the zero-shot run held at the end of each
    stage, shape (n_stages, 4) (a stage never visited takes the previous one's)."""
    out = np.empty((len(trajectory.stages), 4))
    last = trajectory.quats[0]
    for s in range(len(trajectory.stages)):
        rows = np.flatnonzero(trajectory.stage_of == s)
        if len(rows):
            last = trajectory.quats[rows[-1]]
        out[s] = last
    return out


def hand_turns(trajectory: ZeroShotTrajectory) -> NDArray[np.float64]:
    """How far [rad] τ₀'s hand has turned about z since the end of its first stage (the grasp),
    per waypoint, shape (T,); 0 during the first stage."""
    grasped = np.flatnonzero(trajectory.stage_of > 0)
    if not len(grasped):
        return np.zeros(len(trajectory.quats))
    start = Rotation.from_quat(trajectory.quats[max(0, grasped[0] - 1)])
    turn = (Rotation.from_quat(trajectory.quats) * start.inv()).as_rotvec()[:, 2]
    return np.where(trajectory.stage_of > 0, turn, 0.0)


class LearningPolicy:
    """MPC over a learned model with the paper's two sampling distributions.

    Args:
        cost: the task cost (the zero-shot value maps).
        mpc: samples, horizon, σ and the action box.
        prior: the zero-shot trajectory to sample around, or None (uniform sampling).
        orientations: per stage, the end-effector orientation (x, y, z, w), shape (S, 4).
        model: the current dynamics model, or None before the first training.
        anchor_handle: where the zero-shot run observed the handle [m], shape (3,), when there
            is no prior (with one: its ``handle_start``); None: no re-anchoring.
    """

    def __init__(self, cost: TaskCost, mpc: WaypointMPCConfig,
                 prior: ZeroShotTrajectory | None, orientations: NDArray[np.float64],
                 model: StateDynamicsModel | None = None,
                 anchor_handle: NDArray[np.float64] | None = None) -> None:
        self.cost = cost
        self.anchor_handle = anchor_handle if prior is None else prior.handle_start
        self.mpc = mpc
        self.prior = prior
        self.orientations = orientations
        self.model = model
        names = cost.layout.state_names
        #: where the hinged part's observed angle sits in o_t (None: no hinged part)
        self.hinge_index = (cost.layout.index("door_angle") if "door_angle" in names else None)
        self.turns = hand_turns(prior) if prior is not None else None

    def prior_window(self, obs: NDArray[np.float64], step: int) -> tuple[NDArray[np.float64],
                                                                         NDArray[np.float64]]:
        """(prior actions from ``step`` on, shape (H, 4), and their end-effector targets [m],
        shape (H, 3)): toward τ₀'s next waypoints from where the end effector is now."""
        if self.prior is None:
            raise ConfigError("a prior window needs a zero-shot trajectory (prior on)")
        w, g = self.prior.waypoints + self.cost.shift, self.prior.gripper
        h = self.mpc.horizon
        idx = np.minimum(np.arange(step + 1, step + 1 + h), len(w) - 1)
        targets = w[idx]
        starts = np.vstack([obs[None, :3], targets[:-1]])
        return np.column_stack([targets - starts, g[idx]]), targets

    def stage_at(self, step: int) -> int:
        """τ₀'s sub-task at ``step`` with a prior (the stage follows the prior's timing as well
        as the progress made), else 0."""
        if self.prior is None:
            return 0
        return int(self.prior.stage_of[min(step, len(self.prior.stage_of) - 1)])

    def anchor(self, obs: NDArray[np.float64]) -> None:
        """Anchor τ₀ and the task cost to this episode's object: shift them by how far the
        handle observed in ``obs`` (o_0, shape (D_o,)) sits from where the zero-shot run saw it
        (a reset moves the object by up to a few cm). Nothing moves for a τ₀ recorded without
        its handle's start."""
        start = self.anchor_handle
        handle = obs[self.cost.layout.entity_slice(self.cost.layout.parts.handle)]
        self.cost.shift = np.zeros(3) if start is None else np.asarray(handle - start)

    def orientation(self, step: int, stage: int,
                    obs: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """The end-effector orientation (x, y, z, w) to hold during action ``step``: with a prior,
        τ₀'s own at the waypoint the action heads for (τ₀ is a 6-DoF trajectory: the hand turns
        with a hinged part as its rotation map is replanned); without, the zero-shot run's at
        the end of ``stage``. Past the first stage, a hinged part observed in ``obs`` (shape
        (D_o,)) opened further than τ₀'s hand had turned turns the hand about z by the
        difference."""
        if self.prior is not None:
            k = min(step + 1, len(self.prior.quats) - 1)
            quat = self.prior.quats[k]
            turned = float(self.turns[k]) if self.turns is not None else 0.0
        else:
            quat, turned = self.orientations[min(stage, len(self.orientations) - 1)], 0.0
        if obs is None or self.hinge_index is None or stage == 0:
            return np.asarray(quat)
        extra = max(0.0, float(obs[self.hinge_index]) - turned)
        return np.asarray((Rotation.from_rotvec([0.0, 0.0, extra])
                           * Rotation.from_quat(quat)).as_quat())

    def act(self, obs: NDArray[np.float64], step: int, stage: int,
            rng: np.random.Generator) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(a_t, shape (4,), the orientation to hold), see :class:`~voxposer.learning.rollout.
        Policy`."""
        if step == 0:
            self.anchor(obs)
        quat = self.orientation(step, stage, obs)
        prior, targets = (self.prior_window(obs, step) if self.prior is not None
                          else (None, None))
        if self.model is None:
            one = WaypointMPCConfig(self.mpc.action_low, self.mpc.action_high, n_samples=1,
                                    horizon=self.mpc.horizon, sigma=self.mpc.sigma)
            return sample_action_sequences(rng, one, prior)[0, 0], quat

        def cost_fn(predicted: NDArray[np.float64],
                    actions: NDArray[np.float64]) -> NDArray[np.float64]:
            return self.cost(predicted, actions, stage, targets)

        plan = plan_action(self.model, obs, cost_fn, rng, self.mpc, prior)
        return np.asarray(plan.action), quat


__all__ = ["LearningPolicy", "hand_turns", "stage_orientations"]
