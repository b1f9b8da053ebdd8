"""The simulator as the dynamics model: pushes simulated in a private copy of the tabletop.

:class:`SimulatedPush` implements :class:`~voxposer.planning.dynamics.DynamicsModel` by playing
every candidate push in its own MuJoCo copy of the live :class:`~voxposer.envs.TabletopWorld`:
the same scene (``build_scene_spec(world.config)``) with one extra mocap body appended last, a
fingertip-sized probe box, and the Panda's geoms made non-colliding so only the probe touches the
objects. The benchmark's error breakdown (paper Fig. 4) uses it as the counterfactual "perfect
dynamics" model; it is an evaluation oracle (it reads the simulator's ground truth), so it lives
in :mod:`voxposer.bench` and never in a method.

Each push starts from the live world's current state (copied, never modified), so the outcome
includes friction, the contact point's lever arm (the block turns) and neighbours that block or
get pushed along. It simulates every push it is given, one after the other: S pushes cost S
simulations, so callers pass small batches (``PushConfig(n_samples=32)`` to ``64``). Measured on
one (shared, loaded) CPU core with the defaults: about 0.065 s per 6 cm push and 0.05 s per push
on average over the 1–8 cm pushes of :class:`~voxposer.planning.push_primitive.PushConfig`
(1.6 s for 32 pushes); building the private scene, once per instance, about 0.65 s.
"""

from __future__ import annotations

import math
from typing import Final

import mujoco
import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from voxposer.envs.config import WorldConfig
from voxposer.envs.robot_model import BASE_BODY
from voxposer.envs.scene import build_scene_spec
from voxposer.errors import PlanningError, SimulationUnstableError
from voxposer.planning.dynamics.model import PushBatch, PushPrediction

__all__ = ["PROBE_HALF", "SimulatedPush"]

#: Half-sizes [m] of the probe box in its own frame: along the push, across it, vertical (the
#: closed Panda fingertips: 2 cm thick, 7 cm wide across the push, 2 cm high).
PROBE_HALF: Final = (0.01, 0.035, 0.01)
#: The probe's underside stays this far above the table top [m] (no scraping on the table).
_TABLE_CLEARANCE: Final = 0.002
#: Farthest a free body's origin may lie from the given centre to count as the pushed object [m].
MAX_OBJECT_OFFSET_M: Final = 0.1
_PROBE: Final = "sim_push_probe"


def _wxyz_to_rotation(quat: NDArray[np.float64]) -> Rotation:
    """A scipy rotation from MuJoCo quaternions (w, x, y, z), shape (4,) or (N, 4)."""
    return Rotation.from_quat(np.asarray(quat)[..., [1, 2, 3, 0]])


class SimulatedPush:
    """Predicts pushes by simulating each one in a private copy of ``world`` (see the module).

    The probe's front face travels from ``approach_m`` behind the contact point to ``distance``
    past it in a straight line at ``speed_m_s`` (like the primitive's tool, whose centre stops
    its half-thickness short of ``contact + direction * distance``), at the contact's height, its
    long side across the push; then it holds still for ``settle_s`` while the object comes to
    rest. The pushed object is the movable body (a block's free joint, a drawer's slide) with a
    geom nearest the given centre.

    Every push it is given is simulated (~0.05 s each), so the MPC samples :attr:`push_samples`
    pushes per step with it instead of the heuristic's thousands.

    Args:
        world: the live tabletop (a :class:`~voxposer.envs.TabletopWorld`: ``model``, ``data``
            and a :class:`~voxposer.envs.WorldConfig` ``config``); only read, never stepped.
        speed_m_s: probe speed during the push [m/s] (default: the pushing primitive's stroke,
            half the controller's 0.25 m/s).
        approach_m: distance [m] of the probe's front face behind the contact point at the start.
        settle_s: time [s] the probe holds still at the end before the object's pose is read.

    Raises:
        PlanningError: ``world`` is not a MuJoCo tabletop world, or a parameter is not positive
            (``approach_m``, ``settle_s``: not negative).
    """

    #: pushes per MPC step with this model (read by the benchmark's methods).
    push_samples: int = 48

    def __init__(self, world: object, *, speed_m_s: float = 0.125, approach_m: float = 0.02,
                 settle_s: float = 0.2) -> None:
        model, data, config = (getattr(world, k, None) for k in ("model", "data", "config"))
        if not (isinstance(model, mujoco.MjModel) and isinstance(data, mujoco.MjData)
                and isinstance(config, WorldConfig)):
            raise PlanningError(f"SimulatedPush needs a MuJoCo tabletop world with model, data "
                                f"and a WorldConfig config; got {type(world).__name__}")
        for name, value, ok in (("speed_m_s", speed_m_s, speed_m_s > 0),
                                ("approach_m", approach_m, approach_m >= 0),
                                ("settle_s", settle_s, settle_s >= 0)):
            if not (ok and math.isfinite(value)):
                raise PlanningError(f"SimulatedPush.{name} must be finite and "
                                    f"{'> 0' if name == 'speed_m_s' else '>= 0'}; got {value!r}")
        self.live_model, self.live_data = model, data
        self.speed_m_s, self.approach_m, self.settle_s = speed_m_s, approach_m, settle_s
        spec = build_scene_spec(config)
        probe = spec.worldbody.add_body(name=_PROBE, mocap=True, pos=[0.0, 0.0, -10.0])
        geom = probe.add_geom(name=f"{_PROBE}_geom", type=mujoco.mjtGeom.mjGEOM_BOX,
                              size=list(PROBE_HALF), rgba=[0.9, 0.9, 0.9, 1.0])
        geom.contype, geom.conaffinity = 1, 1
        self.model = spec.compile()
        m = self.model
        if (m.nq, m.nv, m.nu, m.na, m.nmocap - 1) != (model.nq, model.nv, model.nu, model.na,
                                                       model.nmocap):
            raise PlanningError(f"the world's model (nq={model.nq}, nmocap={model.nmocap}) is not "
                                "the tabletop scene of its config")
        robot = m.body_rootid[m.geom_bodyid] == m.body(BASE_BODY).id
        m.geom_contype[robot] = 0
        m.geom_conaffinity[robot] = 0
        self.data = mujoco.MjData(m)
        self._probe = int(m.body_mocapid[m.body(_PROBE).id])
        kinds = (int(mujoco.mjtJoint.mjJNT_FREE), int(mujoco.mjtJoint.mjJNT_SLIDE))
        movable = {int(model.jnt_bodyid[j]) for j in range(model.njnt) if int(model.jnt_type[j]) in kinds
                   and m.body_rootid[model.jnt_bodyid[j]] != m.body(BASE_BODY).id}
        #: every body a push can move (a block's free joint, a drawer's slide), and its geoms
        self._bodies = sorted(movable)
        self._geoms = [np.flatnonzero(model.geom_bodyid == b) for b in self._bodies]

    def _object(self, centre: NDArray[np.float64]) -> int:
        """The movable body (a block, a drawer) with a geom nearest ``centre`` [m], shape (3,).

        Raises:
            PlanningError: there is none within :data:`MAX_OBJECT_OFFSET_M`.
        """
        gx = self.live_data.geom_xpos
        gaps = np.array([np.linalg.norm(gx[g] - centre, axis=1).min() if len(g) else np.inf
                         for g in self._geoms])
        k = int(np.argmin(gaps)) if len(gaps) else -1
        if k < 0 or gaps[k] > MAX_OBJECT_OFFSET_M:
            near = (f"{self.live_model.body(self._bodies[k]).name} at {gaps[k]:.3f} m" if k >= 0
                    else "no movable body")
            raise PlanningError(f"no free body within {MAX_OBJECT_OFFSET_M} m of the centre "
                                f"{centre.tolist()} to push (nearest: {near})")
        return self._bodies[k]

    def _simulate(self, contact: NDArray[np.float64], direction: NDArray[np.float64],
                  distance: float, body: int) -> NDArray[np.float64]:
        """One push from the live state; the pushed body's final pose (pos, quat wxyz), (7,)."""
        m, d, live = self.model, self.data, self.live_data
        d.qpos[:], d.qvel[:], d.act[:], d.ctrl[:] = live.qpos, live.qvel, live.act, live.ctrl
        d.qacc_warmstart[:] = live.qacc_warmstart
        d.mocap_pos[:-1], d.mocap_quat[:-1] = live.mocap_pos, live.mocap_quat
        d.xfrc_applied[:] = 0.0
        d.time = live.time
        yaw = math.atan2(direction[1], direction[0])
        d.mocap_quat[self._probe] = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
        height = max(float(contact[2]), PROBE_HALF[2] + _TABLE_CLEARANCE)
        centre0 = np.array([contact[0], contact[1], height]) - direction * PROBE_HALF[0]
        start, travel = centre0 - direction * self.approach_m, self.approach_m + distance
        dt = m.opt.timestep
        n_push = max(1, math.ceil(travel / (self.speed_m_s * dt)))
        bad = d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number
        for k in range(1, n_push + 1):
            d.mocap_pos[self._probe] = start + direction * (travel * k / n_push)
            mujoco.mj_step(m, d)
        mujoco.mj_step(m, d, nstep=max(1, round(self.settle_s / dt)))
        mujoco.mj_kinematics(m, d)
        final = np.concatenate([d.xpos[body], d.xquat[body]])
        if d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number != bad or not np.isfinite(final).all():
            raise SimulationUnstableError(f"the simulated push from {contact.tolist()} along "
                                          f"{direction.tolist()} diverged")
        return final

    def predict(self, centre: NDArray[np.float64], points: NDArray[np.float64],
                pushes: PushBatch) -> PushPrediction:
        """Where the object ends up after each push, simulated (see
        :meth:`DynamicsModel.predict`).

        The object moves rigidly with the pushed body: ``points`` (and ``centre``) are carried
        by the body frame's rotation and translation from its live pose to its simulated final
        pose, so a push off the centre line shows as yaw in the predicted points.

        Args:
            centre: the object's centre [m], shape (3,); the nearest free body is pushed.
            points: the object's points [m], shape (P, 3).
            pushes: S pushes (contacts [m] (S, 3), unit directions (S, 3), distances [m] (S,)).

        Returns:
            centres [m], shape (S, 3), and points [m], shape (S, P, 3).

        Raises:
            PlanningError: no free body lies within 0.1 m of ``centre``.
            SimulationUnstableError: a simulated push diverged.
        """
        c = np.asarray(centre, dtype=np.float64).reshape(3)
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        contacts = np.asarray(pushes.contacts, dtype=np.float64).reshape(-1, 3)
        directions = np.asarray(pushes.directions, dtype=np.float64).reshape(-1, 3)
        distances = np.asarray(pushes.distances, dtype=np.float64).reshape(-1)
        body = self._object(c)
        start = np.concatenate([self.live_data.xpos[body], self.live_data.xquat[body]])
        finals = np.array([self._simulate(contacts[s], directions[s], float(distances[s]), body)
                           for s in range(len(distances))]).reshape(-1, 7)
        turn = (_wxyz_to_rotation(finals[:, 3:]) * _wxyz_to_rotation(start[3:]).inv()).as_matrix()
        moved = np.einsum("sij,pj->spi", turn, pts - start[:3]) + finals[:, None, :3]
        centres = np.einsum("sij,j->si", turn, c - start[:3]) + finals[:, :3]
        return PushPrediction(centres, moved)
