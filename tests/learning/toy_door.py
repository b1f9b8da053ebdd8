"""A test double for the learning loop: a kinematic point robot and a latched toy door.

Not a simulator: the end effector goes exactly where it is sent; a handle at ``HANDLE`` is held
when the gripper closes within 3 cm of it; while held, moving down presses the lever (its angle
grows 10° per cm) and, once pressed past 30°, moving back (−x) drags the handle along. Success:
the handle moved 12 cm back. Its stages are the two sub-tasks a zero-shot program would have
(reach the handle, pull it 20 cm back), and its τ₀ reaches and pulls without pressing far enough
(as the paper's zero-shot trajectories: meaningful but insufficient).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.learning.state import LAYOUTS
from voxposer.learning.zero_shot import Stage, ZeroShotTrajectory

HANDLE = np.array([0.3, 0.0, 0.3])
GRID = VoxelGrid([-0.2, -0.3, 0.0], [0.6, 0.3, 0.6], (40, 30, 30))
QUAT = np.array([0.0, 0.0, 0.0, 1.0])


def stage(entity: str, target: NDArray[np.float64], gripper: float) -> Stage:
    """A stage whose cost is the distance to ``target`` (normalised)."""
    centres = GRID.voxel_to_world(np.indices(GRID.shape).reshape(3, -1).T)
    dist = np.linalg.norm(centres - target, axis=1).reshape(GRID.shape) / GRID.resolution.min()
    return Stage(subtask=f"{entity} to {target.tolist()}", entity=entity, grid=GRID,
                 cost=(dist / dist.max()).astype(np.float32),
                 target_distance=dist.astype(np.float32), gripper=gripper, reached=True)


def trajectory(seed: int = 0) -> ZeroShotTrajectory:
    """τ₀: reach the handle (open), close, press 1 cm (not enough), pull 20 cm back."""
    start = np.array([0.0, 0.0, 0.3])
    reach = np.linspace(start, HANDLE, 11)
    press = np.linspace(HANDLE, HANDLE - [0, 0, 0.01], 3)[1:]
    pull = np.linspace(press[-1], press[-1] - [0.2, 0, 0], 9)[1:]
    wp = np.vstack([reach, press, pull])
    grip = np.r_[np.zeros(len(reach)), np.ones(len(press) + len(pull))]
    stage_of = np.r_[np.zeros(len(reach)), np.ones(len(press) + len(pull))].astype(np.int64)
    stages = (stage("gripper", HANDLE, 0.0), stage("door handle", HANDLE - [0.2, 0, 0], 1.0))
    return ZeroShotTrajectory(task="door", source="toy", seed=seed, waypoints=wp,
                              quats=np.tile(QUAT, (len(wp), 1)), gripper=grip,
                              stage_of=stage_of, period_s=0.25, success=False, stages=stages)


class ToyDoor:
    """The robot-and-door double (see the module docstring)."""

    control_period = 0.05
    grid = GRID

    def __init__(self) -> None:
        self.reset(np.random.default_rng(0))

    def reset(self, rng: np.random.Generator) -> None:
        self.time = 0.0
        self.ee = np.array([0.0, 0.0, 0.3]) + rng.uniform(-0.01, 0.01, 3)
        self.gripper = 0.0
        self.held = False
        self.angle = 0.0
        self.handle = HANDLE.copy()

    def get_ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return self.ee.copy(), QUAT.copy()

    def get_gripper_state(self) -> float:
        return self.gripper

    def step(self, position: Any, quat_xyzw: Any, gripper: float | None = None,
             speed_scale: float = 1.0) -> None:
        target = np.asarray(position, dtype=np.float64)
        move = target - self.ee
        if gripper is not None:
            if gripper >= 0.5 and not self.held and np.linalg.norm(self.ee - self.handle) < 0.03:
                self.held = True
            if gripper < 0.5:
                self.held = False
            self.gripper = float(gripper)
        if self.held:
            self.angle = float(np.clip(self.angle + max(0.0, -move[2]) * 1000.0, 0.0, 45.0))
            if self.angle < 30.0:  # latched: the door does not give
                move[0] = max(move[0], 0.0)
            new_x = min(HANDLE[0], self.handle[0] + move[0])
            move[0] = new_x - self.handle[0]  # the hand stays on the handle
            self.handle = np.array([new_x, self.handle[1], self.handle[2]])
        self.ee = self.ee + move
        self.time += self.control_period

    def success(self) -> tuple[bool, str]:
        moved = float(HANDLE[0] - self.handle[0])
        return moved >= 0.12, f"handle moved {100 * moved:.1f} cm back (needs 12)"


class ToyObserver:
    """o_t of the toy door in the door task's layout (no perception: the double's state)."""

    def __init__(self, door: ToyDoor) -> None:
        self.door = door
        self.layout = LAYOUTS["door"]

    def reset(self) -> None:
        pass

    def observe(self) -> NDArray[np.float64]:
        d = self.door
        return np.r_[d.ee, d.gripper, d.handle, np.radians(d.angle), 0.0]
