"""Disturbances of App. A.4, callable at any step; each returns a record of what it did.

1. :meth:`~DisturbanceMixin.push_robot`: a random external force on a robot link for a while;
2. :meth:`~DisturbanceMixin.displace_object`: move a task-relevant or distractor block elsewhere;
3. :meth:`~DisturbanceMixin.revert_progress`: undo task progress, e.g. pull a drawer back open
   (:meth:`~DisturbanceMixin.pull_drawer`: by a force, through physics);
   :meth:`~DisturbanceMixin.return_object` puts a pushed block back toward its start.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.catalog import DRAWERS
from voxposer.envs.config import WorldConfig
from voxposer.envs.layout import PLACE_MAX, PLACE_MIN
from voxposer.envs.registry import ObjectRegistry
from voxposer.envs.robot_model import EE_SITE, PREFIX
from voxposer.errors import LayoutError
from voxposer.tabletop import DRAWER_TRAVEL

#: Links a random force may hit.
PUSHABLE_LINKS = tuple(f"{PREFIX}link{i}" for i in range(3, 8)) + (f"{PREFIX}hand_right_gripper",)


@dataclass(frozen=True)
class Disturbance:
    """What a disturbance did.

    Attributes:
        kind: "force", "displace" or "revert".
        target: the body or object disturbed ("panda_link5", "blue block", "top drawer").
        before: the disturbed quantity before: position [m] (3,) for objects, opening [m] (1,)
            for drawers, the link position [m] (3,) for forces.
        after: the same quantity after (for forces: the force vector [N], shape (3,)).
        duration: how long a force acts [s]; 0 for instantaneous disturbances.
        time: simulation time when it was applied [s].
    """

    kind: str
    target: str
    before: NDArray[np.float64]
    after: NDArray[np.float64]
    duration: float
    time: float


class DisturbanceMixin:
    """Disturbances of the :class:`~voxposer.envs.world.TabletopWorld` (see module docstring)."""

    config: WorldConfig
    model: mujoco.MjModel
    data: mujoco.MjData
    registry: ObjectRegistry
    _present: tuple[str, ...]
    _force: tuple[int, NDArray[np.float64], int] | None
    _obs: Any

    def push_robot(self, rng: np.random.Generator, *, magnitude: tuple[float, float] = (15.0, 30.0),
                   duration: float = 0.3, link: str | None = None) -> Disturbance:
        """Apply a random horizontal-ish force [N] to a robot link for ``duration`` [s].

        The force acts during the next physics steps (``step``/``move_to_pose`` calls).
        """
        name = link or str(rng.choice(PUSHABLE_LINKS))
        body = self.model.body(name).id
        direction = rng.normal(size=3)
        direction[2] *= 0.3
        direction /= np.linalg.norm(direction)
        force = direction * float(rng.uniform(*magnitude))
        wrench = np.concatenate([force, np.zeros(3)])
        steps = max(1, round(duration / self.config.timestep))
        self._force = (body, wrench, steps)
        return Disturbance("force", name, self.data.xpos[body].copy(), force, duration,
                           float(self.data.time))

    def displace_object(self, rng: np.random.Generator, name: str | None = None, *,
                        min_distance: float = 0.08, max_distance: float = 0.25) -> Disturbance:
        """Move a block (``name`` or a random present block) to a free random spot on the table.

        Raises:
            LayoutError: no block is present, or no free spot was found.
        """
        blocks = [n for n in self._present if n.endswith(" block")]
        if name is None:
            if not blocks:
                raise LayoutError("no block is present to displace")
            name = str(rng.choice(blocks))
        obj = self.registry.resolve(name, tuple(blocks))
        adr = self.model.joint(f"{self.registry.body(obj.name)}_joint").qposadr[0]
        dof = self.model.joint(f"{self.registry.body(obj.name)}_joint").dofadr[0]
        before = self.data.qpos[adr:adr + 3].copy()
        others = [self.data.xpos[self.model.body(self.registry.body(b)).id][:2]
                  for b in blocks if b != obj.name]
        clearance = self.config.block_size * 1.6
        for _ in range(200):
            angle = rng.uniform(0.0, 2.0 * math.pi)
            dist = rng.uniform(min_distance, max_distance)
            xy = before[:2] + dist * np.array([math.cos(angle), math.sin(angle)])
            inside = np.all(xy >= PLACE_MIN) and np.all(xy <= PLACE_MAX)
            if inside and all(np.linalg.norm(xy - o) >= clearance for o in others):
                break
        else:
            raise LayoutError(f"no free spot found to displace the {obj.name}")
        after = self._put_block(adr, dof, xy)
        return Disturbance("displace", obj.name, before, after, 0.0, float(self.data.time))

    def return_object(self, rng: np.random.Generator, name: str, to: ArrayLike, *,
                      undo: tuple[float, float] = (0.5, 1.0), hand_clearance: float = 0.06
                      ) -> Disturbance:
        """Undo a random fraction ``undo`` of a block's progress: move it from where it is back
        toward ``to`` (x, y[, z]) [m], e.g. where a push started, onto a free spot at least
        ``hand_clearance`` [m] (horizontally) from the hand.

        Raises:
            LayoutError: the block is not present, has not moved 2 cm from ``to``, or no free
                spot was found.
        """
        blocks = [n for n in self._present if n.endswith(" block")]
        obj = self.registry.resolve(name, tuple(blocks))
        adr = self.model.joint(f"{self.registry.body(obj.name)}_joint").qposadr[0]
        dof = self.model.joint(f"{self.registry.body(obj.name)}_joint").dofadr[0]
        before = self.data.qpos[adr:adr + 3].copy()
        back = np.asarray(to, dtype=np.float64).reshape(-1)[:2] - before[:2]
        if float(np.linalg.norm(back)) < 0.02:
            raise LayoutError(f"the {obj.name} has made no progress to revert")
        others = [self.data.xpos[self.model.body(self.registry.body(b)).id][:2]
                  for b in blocks if b != obj.name]
        hand = self.data.site_xpos[self.model.site(EE_SITE).id][:2]
        clearance = self.config.block_size * 1.6
        for _ in range(50):
            xy = before[:2] + float(rng.uniform(*undo)) * back
            inside = np.all(xy >= PLACE_MIN) and np.all(xy <= PLACE_MAX)
            if inside and np.linalg.norm(xy - hand) >= hand_clearance and all(
                    np.linalg.norm(xy - o) >= clearance for o in others):
                break
        else:
            raise LayoutError(f"no free spot found to put the {obj.name} back")
        after = self._put_block(adr, dof, xy)
        return Disturbance("revert", obj.name, before, after, 0.0, float(self.data.time))

    def _put_block(self, adr: int, dof: int, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """Set a block (free joint at qpos ``adr``, dofs ``dof``) down at rest at ``xy`` [m];
        returns its new position [m], shape (3,)."""
        after = np.array([xy[0], xy[1], self.config.block_size / 2])
        self.data.qpos[adr:adr + 3] = after
        self.data.qvel[dof:dof + 6] = 0.0
        mujoco.mj_forward(self.model, self.data)
        self._obs = None
        return after

    def _drawer_joint(self, rng: np.random.Generator, drawer: str | None) -> tuple[Any, Any]:
        """(registry object, MuJoCo joint) of ``drawer`` or a random drawer.

        Raises:
            LayoutError: the cabinet is not in the scene.
        """
        if "cabinet" not in self._present:
            raise LayoutError("the cabinet is not in the scene; there is no progress to revert")
        which = (drawer or str(rng.choice(DRAWERS))).lower().removesuffix(" drawer").strip()
        obj = self.registry.resolve(f"{which} drawer", self._present)
        return obj, self.model.joint(f"{self.registry.body(obj.name)}_joint")

    def pull_drawer(self, rng: np.random.Generator, drawer: str | None = None, *,
                    force: tuple[float, float] = (30.0, 50.0), duration: float = 0.1
                    ) -> Disturbance:
        """Yank a drawer (``drawer`` or a random one) open: a random force [N] along its
        opening direction for ``duration`` [s] (a free drawer opens most of its travel).

        Unlike :meth:`revert_progress` the drawer moves by physics: a hand in front of it is
        pushed back, not passed through. The force acts during the next physics steps
        (replacing a force of :meth:`push_robot` still acting).

        Raises:
            LayoutError: the cabinet is not in the scene.
        """
        obj, joint = self._drawer_joint(rng, drawer)
        body = int(self.model.jnt_bodyid[joint.id])
        axis = self.data.xmat[body].reshape(3, 3) @ \
            self.model.jnt_axis[joint.id]
        pull = axis / np.linalg.norm(axis) * float(rng.uniform(*force))
        steps = max(1, round(duration / self.config.timestep))
        self._force = (body, np.concatenate([pull, np.zeros(3)]), steps)
        opening = float(self.data.qpos[joint.qposadr[0]])
        return Disturbance("revert", obj.name, np.array([opening]), pull, duration,
                           float(self.data.time))

    def revert_progress(self, rng: np.random.Generator, drawer: str | None = None, *,
                        opening: tuple[float, float] = (0.10, 0.18)) -> Disturbance:
        """Pull a drawer (``drawer`` or a random one) open by a random amount [m].

        Raises:
            LayoutError: the cabinet is not in the scene.
        """
        obj, joint = self._drawer_joint(rng, drawer)
        adr, dof = joint.qposadr[0], joint.dofadr[0]
        before = float(self.data.qpos[adr])
        after = float(np.clip(rng.uniform(*opening), 0.0, DRAWER_TRAVEL))
        self.data.qpos[adr] = after
        self.data.qvel[dof] = 0.0
        mujoco.mj_forward(self.model, self.data)
        self._obs = None
        return Disturbance("revert", obj.name, np.array([before]), np.array([after]), 0.0,
                           float(self.data.time))
