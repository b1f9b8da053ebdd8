"""What the language model programs perceive: the :class:`Scene` protocol and a box scene.

The LMP context needs only ``detect(name)``, ``object_names``, ``grid``, ``ee_pose()`` and
``gripper_state()``. A robot and its perceiver plug in through :class:`RobotScene`; tests, the
``voxposer lmp`` command and the accuracy benchmark use :class:`BoxScene`, a static scene of
axis-aligned boxes (:func:`make_tabletop_scene` lays out the simulator's tabletop from the same
description, :mod:`voxposer.tabletop`: table, cabinet with three drawers and handles, ten blocks
and ten lines).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer import tabletop
from voxposer.catalog import COLOR_NAMES
from voxposer.errors import ConfigError, UnknownObjectError
from voxposer.geometry.frames import TOP_DOWN_QUAT
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.detect import DetectedObject
from voxposer.perception.perceiver import Perceiver
from voxposer.robot import Robot


@runtime_checkable
class Scene(Protocol):
    """The perception interface the LMP context uses (world frame, metres)."""

    @property
    def grid(self) -> VoxelGrid:
        """The workspace voxel grid."""

    @property
    def object_names(self) -> tuple[str, ...]:
        """Canonical names of the objects ``detect`` accepts."""

    def detect(self, name: str) -> Any:
        """Object ``name`` with ``position`` (3,), ``aabb`` (2, 3) [m], ``occupancy`` (grid
        shape, bool), ``normal`` (3,) and ``points`` (N, 3) [m]; attribute or item access."""

    def ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """End-effector position [m], shape (3,), and quaternion (x, y, z, w)."""

    def gripper_state(self) -> float:
        """Gripper state: 1.0 closed, 0.0 open."""


@dataclass
class Box:
    """An axis-aligned box object.

    Attributes:
        lo, hi: lower and upper corners [m], shape (3,).
        normal: mean outward surface normal reported by ``detect`` (unit, shape (3,)).
    """

    lo: NDArray[np.float64]
    hi: NDArray[np.float64]
    normal: NDArray[np.float64]


class BoxScene:
    """A static scene of named boxes; objects can be moved to emulate a changing world.

    Args:
        grid: workspace grid.
        boxes: name → (lo, hi) corners [m] or (lo, hi, normal).
        ee_position: end-effector position [m]; a small "gripper" box follows it.
        gripper: gripper state (1 closed, 0 open).
    """

    def __init__(self, grid: VoxelGrid, boxes: Mapping[str, tuple[ArrayLike, ...]],
                 ee_position: ArrayLike = (-0.25, 0.0, 0.40), gripper: float = 0.0) -> None:
        self._grid = grid
        self._boxes: dict[str, Box] = {}
        for name, spec in boxes.items():
            if len(spec) not in (2, 3):
                raise ConfigError(f"box {name!r} needs (lo, hi) or (lo, hi, normal); got {spec!r}")
            lo, hi = np.asarray(spec[0], float), np.asarray(spec[1], float)
            if lo.shape != (3,) or hi.shape != (3,) or np.any(lo >= hi):
                raise ConfigError(f"box {name!r} must have lo < hi, shape (3,); got {lo}, {hi}")
            normal = np.asarray(spec[2], float) if len(spec) == 3 else np.zeros(3)
            self._boxes[name] = Box(lo, hi, normal)
        self.ee_quat = np.asarray(TOP_DOWN_QUAT, float)
        self.set_ee(ee_position)
        self.gripper = float(gripper)
        self.detect_calls = 0

    @property
    def grid(self) -> VoxelGrid:
        return self._grid

    @property
    def object_names(self) -> tuple[str, ...]:
        return tuple(self._boxes)

    def set_ee(self, position: ArrayLike) -> None:
        """Move the end effector (and the "gripper" box) to ``position`` [m]."""
        self.ee_position = np.asarray(position, float).reshape(3)
        half = np.array([0.02, 0.04, 0.02])
        self._boxes["gripper"] = Box(self.ee_position - half, self.ee_position + half,
                                     np.array([0.0, 0.0, -1.0]))

    def move(self, name: str, delta: ArrayLike) -> None:
        """Translate object ``name`` by ``delta`` [m], shape (3,)."""
        if name not in self._boxes:
            raise UnknownObjectError(name, self._boxes)
        d = np.asarray(delta, float).reshape(3)
        box = self._boxes[name]
        self._boxes[name] = Box(box.lo + d, box.hi + d, box.normal)

    def set_box(self, name: str, lo: ArrayLike, hi: ArrayLike) -> None:
        """Give object ``name`` the box [lo, hi] [m] (e.g. the part of a drawer left in view)."""
        box = self.box(name)
        self._boxes[name] = Box(np.asarray(lo, float).reshape(3), np.asarray(hi, float).reshape(3),
                                box.normal)

    def box(self, name: str) -> Box:
        """The box of object ``name`` (exact name)."""
        if name not in self._boxes:
            raise UnknownObjectError(name, self._boxes)
        return self._boxes[name]

    def detect(self, name: str) -> DetectedObject:
        """The object called exactly ``name`` (the LMP API does the lenient matching)."""
        box = self.box(name)
        self.detect_calls += 1
        points = _box_points(box.lo, box.hi)
        occupancy = np.zeros(self._grid.shape, dtype=bool)
        inside = self._grid.contains(points)
        if np.any(inside):
            lo = self._grid.world_to_voxel(np.clip(box.lo, self._grid.bounds_min,
                                                   self._grid.bounds_max))
            hi = self._grid.world_to_voxel(np.clip(box.hi, self._grid.bounds_min,
                                                   self._grid.bounds_max))
            occupancy[lo[0]:hi[0] + 1, lo[1]:hi[1] + 1, lo[2]:hi[2] + 1] = True
        normals = np.broadcast_to(box.normal, points.shape).copy()
        return DetectedObject(name=name, position=(box.lo + box.hi) / 2.0,
                              aabb=np.stack([box.lo, box.hi]), occupancy=occupancy,
                              normal=box.normal.copy(), points=points, normals=normals)

    def ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return self.ee_position.copy(), self.ee_quat.copy()

    def gripper_state(self) -> float:
        return self.gripper


def _box_points(lo: NDArray[np.float64], hi: NDArray[np.float64]) -> NDArray[np.float64]:
    """The 8 corners and the centre of a box [m], shape (9, 3) (enough for a box scene)."""
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                        for z in (lo[2], hi[2])])
    return np.vstack([corners, (lo + hi) / 2.0])


class RobotScene:
    """The :class:`Scene` of a robot and its perception: objects from a
    :class:`~voxposer.perception.perceiver.Perceiver`, the end effector and gripper from a
    :class:`~voxposer.robot.Robot` (the MuJoCo world is both)."""

    def __init__(self, perceiver: Perceiver, robot: Robot) -> None:
        self.perceiver = perceiver
        self.robot = robot

    @property
    def grid(self) -> VoxelGrid:
        return self.perceiver.grid

    @property
    def object_names(self) -> tuple[str, ...]:
        return tuple(self.perceiver.object_names)

    def detect(self, name: str) -> Any:
        return self.perceiver.detect(name)

    def ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        pos, quat = self.robot.get_ee_pose()
        return np.asarray(pos, float), np.asarray(quat, float)

    def gripper_state(self) -> float:
        return float(self.robot.get_gripper_state())


#: Block centres (x, y) [m] in the fixed tabletop scene (all clear of the cabinet).
BLOCK_XY = {
    "blue": (0.05, -0.20), "green": (-0.10, 0.05), "yellow": (0.10, 0.15),
    "pink": (-0.25, -0.25), "brown": (-0.05, -0.35), "red": (0.12, -0.05),
    "orange": (-0.20, -0.05), "purple": (-0.35, 0.30), "cyan": (-0.30, 0.10),
    "gray": (0.20, 0.30),
}


def make_tabletop_scene() -> BoxScene:
    """The fixed tabletop scene used by ``voxposer lmp`` and the accuracy benchmark.

    Built from the one layout description (:mod:`voxposer.tabletop`) that the simulator is built
    from: the same table, workspace grid and cabinet (its drawers open toward −y, a handle on
    each drawer front), the robot as a column over its base, ten 5 cm blocks at fixed places
    and ten 20 cm lines along y.
    """
    grid = VoxelGrid(tabletop.WORKSPACE_MIN, tabletop.WORKSPACE_MAX, tabletop.GRID_SHAPE)
    (x0, y0), (x1, y1) = tabletop.TABLE_MIN, tabletop.TABLE_MAX
    boxes: dict[str, tuple[ArrayLike, ...]] = {
        "table": ((x0, y0, -0.02), (x1, y1, 0.0), (0.0, 0.0, 1.0)),
    }
    cx, cy = tabletop.CABINET_POSITION
    sx, sy, sz = (s / 2 for s in tabletop.CABINET_SIZE)
    boxes["cabinet"] = ((cx - sx, cy - sy, 0.0), (cx + sx, cy + sy, 2 * sz))
    hx, hy, hz = tabletop.HANDLE_HALF
    for slot in tabletop.drawer_slots():
        z0, z1 = slot.centre_z - slot.half_height, slot.centre_z + slot.half_height
        boxes[f"{slot.name} drawer"] = ((cx - sx, cy - sy, z0), (cx + sx, cy + sy, z1), (0, -1, 0))
        hc = cy - sy - tabletop.HANDLE_STANDOFF
        boxes[f"{slot.name} drawer handle"] = ((cx - hx, hc - hy, slot.centre_z - hz),
                                               (cx + hx, hc + hy, slot.centre_z + hz),
                                               (0.0, -1.0, 0.0))
    bx, by, _ = tabletop.ROBOT_BASE  # the arm's column over its base (the simulator's robot)
    boxes["robot"] = ((bx - 0.08, by - 0.08, 0.0), (bx + 0.08, by + 0.08, 0.35))
    half = tabletop.BLOCK_SIZE / 2
    for colour, (x, y) in BLOCK_XY.items():
        boxes[f"{colour} block"] = ((x - half, y - half, 0.0), (x + half, y + half, 2 * half))
    lw, ll = tabletop.LINE_WIDTH / 2, tabletop.LINE_LENGTH / 2
    for k, colour in enumerate(COLOR_NAMES):
        x = -0.55 + 0.07 * k
        y = -0.12 if k % 2 == 0 else 0.12
        boxes[f"{colour} line"] = ((x - lw, y - ll, 0.0), (x + lw, y + ll, 0.002),
                                   (0.0, 0.0, 1.0))
    return BoxScene(grid, boxes)
