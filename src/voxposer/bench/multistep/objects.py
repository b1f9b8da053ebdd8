"""Steps that change an object: push a block to a place, grasp and lift it, drop it at a place,
close a drawer.

Each reuses the 13 tasks' reference builders (``push_programs``, ``grasp_programs``,
``carry_and_release_programs``, ``push_handle_programs``) and judges its condition at every
trace sample. Object states persist (a later step must not undo them), except "held".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import BLOCK_HALF
from voxposer.bench.multistep.step import Step, back_to_default
from voxposer.bench.programs import Programs
from voxposer.bench.tasks.close_drawer import push_handle_programs
from voxposer.bench.tasks.drop_to_pos import carry_and_release_programs
from voxposer.bench.tasks.grasp_at_velocity import grasp_programs
from voxposer.bench.tasks.push_to_pos import push_programs
from voxposer.bench.trace import Trace
from voxposer.places import get_place


def resting_at(positions: NDArray[np.float64], place: str, tol: Tolerances) -> NDArray[np.bool_]:
    """Whether blocks centred at ``positions`` [m], shape (T, 3), rest on the table at
    ``place`` (as :func:`~voxposer.bench.measures.block_at_place` judges one), shape (T,)."""
    inside = get_place(place).margin(positions[:, :2], tol.corner_radius_m) >= 0
    return np.asarray(inside & (positions[:, 2] <= tol.rest_height_m))


def _where(obj: str, place: str, positions: NDArray[np.float64], tol: Tolerances) -> str:
    """"the blue block ends 4.0 cm outside it, 2.5 cm high"."""
    margin = float(get_place(place).margin(positions[-1, :2], tol.corner_radius_m))
    return (f"the {obj} ends {max(-margin, 0.0) * 100:.1f} cm outside it, "
            f"{positions[-1, 2] * 100:.1f} cm high")


@dataclass(frozen=True)
class PushedTo(Step):
    """Block ``obj`` resting at table place ``place`` ("push the [obj] to the [pos]")."""

    obj: str
    place: str
    persists: ClassVar[bool] = True

    @property
    def label(self) -> str:
        return f"push the {self.obj} to the {self.place}"

    def tracked(self) -> tuple[str, ...]:
        return (self.obj,)

    def held(self, world: Any, trace: Trace, tol: Tolerances) -> NDArray[np.bool_]:
        return resting_at(trace.objects[self.obj], self.place, tol)

    def describe_end(self, world: Any, trace: Trace, tol: Tolerances) -> str:
        return _where(self.obj, self.place, trace.objects[self.obj], tol)

    def programs(self, progs: Programs) -> list[str]:
        push_programs(progs, self.obj, get_place(self.place))
        return [f"push the {self.obj} to the {get_place(self.place).name}"]


@dataclass(frozen=True)
class Held(Step):
    """Block ``obj`` grasped and lifted: the gripper commanded closed, the block's centre within
    ``held_distance_m`` of the end effector and ``lift_m`` off the table ("grasp the [obj]").
    The reference grasps it top-down and lifts it back to the ready pose."""

    obj: str

    @property
    def label(self) -> str:
        return f"grasp the {self.obj}"

    def tracked(self) -> tuple[str, ...]:
        return (self.obj,)

    def _parts(self, trace: Trace) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        block = trace.objects[self.obj]
        return (np.asarray(np.linalg.norm(block - trace.ee, axis=1), dtype=np.float64),
                np.asarray(block[:, 2] - BLOCK_HALF, dtype=np.float64))

    def held(self, world: Any, trace: Trace, tol: Tolerances) -> NDArray[np.bool_]:
        dist, lifted = self._parts(trace)
        return np.asarray((trace.gripper >= 0.5) & (dist <= tol.held_distance_m)
                          & (lifted >= tol.lift_m))

    def describe_end(self, world: Any, trace: Trace, tol: Tolerances) -> str:
        dist, lifted = self._parts(trace)
        return (f"at most {float(np.max(lifted)) * 100:.1f} cm off the table; at the end "
                f"{dist[-1] * 100:.1f} cm from the hand, gripper "
                f"{'closed' if trace.gripper[-1] >= 0.5 else 'open'}")

    def programs(self, progs: Programs) -> list[str]:
        grasp_programs(progs, self.obj)
        return [f"grasp the {self.obj}", back_to_default(progs)]


@dataclass(frozen=True)
class DroppedAt(Step):
    """Block ``obj`` resting at ``place`` with the gripper open ("drop it to the [pos]"); the
    reference carries the held block 10 cm above the place, releases it, and goes back to the
    ready pose."""

    obj: str
    place: str
    persists: ClassVar[bool] = True

    @property
    def label(self) -> str:
        return f"drop the {self.obj} to the {self.place}"

    def tracked(self) -> tuple[str, ...]:
        return (self.obj,)

    def held(self, world: Any, trace: Trace, tol: Tolerances) -> NDArray[np.bool_]:
        return np.asarray(resting_at(trace.objects[self.obj], self.place, tol)
                          & (trace.gripper < 0.5))

    def describe_end(self, world: Any, trace: Trace, tol: Tolerances) -> str:
        where = _where(self.obj, self.place, trace.objects[self.obj], tol)
        return where + ("" if trace.gripper[-1] < 0.5 else ", still held")

    def programs(self, progs: Programs) -> list[str]:
        steps = carry_and_release_programs(progs, self.obj, get_place(self.place))
        return [*steps, back_to_default(progs)]


@dataclass(frozen=True)
class DrawerClosed(Step):
    """The ``which`` drawer ("top", "middle", "bottom") open less than ``drawer_closed_m``
    ("close the [deixis] drawer by pushing"). The trace records the drawer body's position;
    its opening at a sample is the final opening plus the displacement from the final
    position along the drawer's axis."""

    which: str
    persists: ClassVar[bool] = True

    @property
    def label(self) -> str:
        return f"close the {self.which} drawer"

    def tracked(self) -> tuple[str, ...]:
        return (f"{self.which} drawer",)

    def openings(self, world: Any, trace: Trace) -> NDArray[np.float64]:
        """The drawer's opening [m] at each sample, shape (T,)."""
        body = trace.objects[f"{self.which} drawer"]
        axis = world.drawer_axis(self.which)
        return np.asarray(world.drawer_opening(self.which) + (body - body[-1]) @ axis,
                          dtype=np.float64)

    def held(self, world: Any, trace: Trace, tol: Tolerances) -> NDArray[np.bool_]:
        return self.openings(world, trace) < tol.drawer_closed_m

    def describe_end(self, world: Any, trace: Trace, tol: Tolerances) -> str:
        return f"the {self.which} drawer ends open {world.drawer_opening(self.which) * 100:.1f} cm"

    def programs(self, progs: Programs) -> list[str]:
        return [push_handle_programs(progs, self.which), back_to_default(progs)]
