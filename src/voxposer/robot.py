"""The robot seam: what closed-loop execution may ask of an arm with a gripper.

A base module: the simulator implements :class:`Robot` (:class:`voxposer.envs.TabletopWorld`),
a kinematic stand-in in the tests implements it, a real arm's driver would; the executor
(:mod:`voxposer.control`) uses nothing else of a robot. Positions are world-frame metres;
quaternions scalar-last (x, y, z, w); the approach axis is the end effector's local +z.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray


@dataclass(frozen=True)
class StepResult:
    """Outcome of one control period.

    Attributes:
        ee_position: measured end-effector position [m] after the step, shape (3,).
        at_goal: the interpolated reference has reached the commanded pose.
        time: the robot's clock [s].
    """

    ee_position: NDArray[np.float64]
    at_goal: bool
    time: float


@dataclass(frozen=True)
class MoveResult:
    """Outcome of :meth:`Robot.move_to_pose`: the caller must look at ``reached``.

    Attributes:
        reached: the measured pose ended within the controller tolerances of the target.
        position_error: final distance to the target position [m].
        rotation_error: final angle to the target orientation [rad].
        duration: time the move took [s].
    """

    reached: bool
    position_error: float
    rotation_error: float
    duration: float


@runtime_checkable
class Robot(Protocol):
    """An arm with a parallel gripper, commanded in end-effector poses."""

    @property
    def control_period(self) -> float:
        """Duration of one :meth:`step` [s]."""
        ...

    @property
    def time(self) -> float:
        """The robot's clock [s] (simulated time in simulation)."""
        ...

    @property
    def ee_speed(self) -> float:
        """End-effector linear speed at ``speed_scale=1`` [m/s]."""
        ...

    @property
    def base_position(self) -> NDArray[np.float64]:
        """Position of the arm's base [m], shape (3,)."""
        ...

    def get_ee_pose(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """End-effector position [m], shape (3,), and orientation (x, y, z, w)."""
        ...

    def joint_positions(self) -> NDArray[np.float64]:
        """Arm joint angles [rad], shape (n_joints,)."""
        ...

    def step(self, position: ArrayLike, quat_xyzw: ArrayLike, gripper: float | None = None,
             speed_scale: float = 1.0) -> StepResult:
        """One control period toward an end-effector pose (gripper 1 close, 0 open)."""
        ...

    def move_to_pose(self, position: ArrayLike, quat_xyzw: ArrayLike | None = None,
                     speed_scale: float = 1.0, gripper: float | None = None,
                     max_detour: float | None = None) -> MoveResult:
        """Move to a pose and wait; raises ``UnreachablePoseError`` if no joint configuration
        reaches it (the robot does not move); a move that ends short says so in its result.
        ``max_detour`` [m]: how far the hand may leave the straight line to the target to
        finish a move whose line the arm cannot follow (None: no limit; 0: it stops where the
        line got stuck — a push's stroke)."""
        ...

    def get_gripper_state(self) -> float:
        """Commanded gripper state: 1.0 closed, 0.0 open."""
        ...

    def gripper_opening(self) -> float:
        """Measured distance between the fingers [m]."""
        ...

    def open_gripper(self) -> None:
        """Open the fingers and wait until they are open."""
        ...

    def close_gripper(self) -> None:
        """Close the fingers and wait until they are closed."""
        ...

    def reset_to_default_pose(self, speed_scale: float = 1.0) -> MoveResult:
        """Move back to the ready pose."""
        ...


__all__ = ["MoveResult", "Robot", "StepResult"]
