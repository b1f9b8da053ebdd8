"""Typed configuration of the articulated scenes (paper Sec. 4.3, Table 3): door, window, fridge.

World frame as on the tabletop (:mod:`voxposer.envs.config`): metres, z up, the table top is
z = 0, the robot base stands at the back (−x) facing +x. Each object stands on the table in front
of the robot with its handle facing the robot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Final

from voxposer import tabletop
from voxposer.config_checks import require_non_negative, require_positive
from voxposer.envs.config import CameraConfig, ControllerConfig, check_world_timing
from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid

#: Largest angle the door lever turns down [rad] (its joint's stop).
LEVER_TRAVEL: Final = math.radians(45.0)
#: Largest opening of the door and of the fridge door [rad].
HINGE_TRAVEL: Final = math.radians(100.0)
#: How far the window sash slides [m].
SASH_TRAVEL: Final = 0.28


def _below(name: str, value: float, limit: float, what: str) -> None:
    if value >= limit:
        raise ConfigError(f"{name} must be below {what} ({limit:.4g}); got {value!r}")


@dataclass(frozen=True)
class DoorConfig:
    """A door on a vertical hinge with a lever handle and a latch.

    The latch holds the door within ``latch_play`` of closed until the lever is pressed down
    past ``unlatch_angle``; once the door has swung out it is free until it is closed again.

    Attributes:
        success_angle: the door counts as open from this angle [rad] (default 25°).
        unlatch_angle: lever angle that frees the latch [rad] (default 30°; the lever stops at 45°).
        latch_play: how far a latched door can move [rad] (default 0.5°).
        lever_stiffness: the lever's return spring [N m/rad]; it rests against its stop with a
            preload of ``0.4 * lever_stiffness`` [N m].
        hinge_damping: door hinge damping [N m s/rad].
        hinge_friction: door hinge dry friction [N m].
    """

    success_angle: float = math.radians(25.0)
    unlatch_angle: float = math.radians(30.0)
    latch_play: float = math.radians(0.5)
    lever_stiffness: float = 0.5
    hinge_damping: float = 0.5
    hinge_friction: float = 0.2

    def __post_init__(self) -> None:
        require_positive(self, "success_angle", "unlatch_angle", "latch_play", "lever_stiffness")
        require_non_negative(self, "hinge_damping", "hinge_friction")
        _below("DoorConfig.unlatch_angle", self.unlatch_angle, LEVER_TRAVEL, "the lever's travel")
        _below("DoorConfig.success_angle", self.success_angle, HINGE_TRAVEL, "the hinge's travel")
        _below("DoorConfig.latch_play", self.latch_play, self.success_angle, "success_angle")


@dataclass(frozen=True)
class WindowConfig:
    """A window sash sliding sideways (to the left, −y) in its frame.

    Attributes:
        success_offset: the window counts as open from this offset [m] (default 0.12).
        frictionloss: dry friction of the slide [N]: a lighter sideways force does not move it.
        damping: viscous damping of the slide [N s/m].
    """

    success_offset: float = 0.12
    frictionloss: float = 6.0
    damping: float = 15.0

    def __post_init__(self) -> None:
        require_positive(self, "success_offset", "frictionloss")
        require_non_negative(self, "damping")
        _below("WindowConfig.success_offset", self.success_offset, SASH_TRAVEL, "the sash's travel")


@dataclass(frozen=True)
class FridgeConfig:
    """A fridge whose door is held closed by a magnetic seal.

    The seal pulls the door closed with the torque of ``seal_force`` at the handle while the
    door is within ``seal_range / 5`` of closed, fading linearly to nothing at ``seal_range``; a
    pull on the handle, normal to the door, opens it when stronger than ``seal_force`` (the
    hinge's own friction included).

    Attributes:
        success_angle: the door counts as open from this angle [rad] (default 30°).
        seal_force: pull at the handle that opens the closed door [N] (default 15).
        seal_range: door angle beyond which the seal no longer acts [rad] (default 3°).
        hinge_damping: door hinge damping [N m s/rad].
        hinge_friction: door hinge dry friction [N m] (less than the seal's torque).
    """

    success_angle: float = math.radians(30.0)
    seal_force: float = 15.0
    seal_range: float = math.radians(3.0)
    hinge_damping: float = 0.3
    hinge_friction: float = 0.1

    def __post_init__(self) -> None:
        require_positive(self, "success_angle", "seal_force", "seal_range")
        require_non_negative(self, "hinge_damping", "hinge_friction")
        _below("FridgeConfig.success_angle", self.success_angle, HINGE_TRAVEL, "the hinge's travel")
        _below("FridgeConfig.seal_range", self.seal_range, self.success_angle, "success_angle")


def _default_cameras() -> CameraConfig:
    """Four RGB-D cameras on the robot's side of the object (the handles face the robot)."""
    return CameraConfig(
        target=(0.05, 0.0, 0.35),
        positions=(
            ("front_left", (-0.10, -0.85, 0.75)),
            ("front_right", (-0.10, 0.85, 0.75)),
            ("back_left", (-0.75, -0.55, 0.95)),
            ("back_right", (-0.75, 0.55, 0.95)),
        ),
    )


@dataclass(frozen=True)
class ArticulatedConfig:
    """An articulated scene: robot, table, physics, randomisation and each object's mechanism.

    A reset draws, uniformly and independently: each arm joint within ``±joint_noise`` of the
    home pose; the object's base within ``±position_noise`` of its nominal x and y; its yaw
    within ``±yaw_noise``.

    Attributes:
        timestep: physics step [s].
        robot_base: position of the robot base [m] (back of the table, facing +x).
        table_min, table_max: table top extent in x, y [m]; its surface is z = 0.
        workspace_min, workspace_max: the voxel workspace box [m]; grid_shape: voxels per axis.
        position_noise: object placement noise in x and y [m] (default 0.02).
        yaw_noise: object yaw noise [rad] (default 5°).
        joint_noise: arm start noise per joint [rad] (default 0.05).
        door, window, fridge: the objects' mechanisms and success thresholds.
        cameras, controller: nested configs (cameras named as on the tabletop).
    """

    timestep: float = 0.002
    robot_base: tuple[float, float, float] = tabletop.ROBOT_BASE
    table_min: tuple[float, float] = (-0.70, -0.50)
    table_max: tuple[float, float] = (0.50, 0.50)
    workspace_min: tuple[float, float, float] = (-0.70, -0.50, -0.02)
    workspace_max: tuple[float, float, float] = (0.50, 0.50, 0.98)
    grid_shape: tuple[int, int, int] = (120, 100, 100)
    position_noise: float = 0.02
    yaw_noise: float = math.radians(5.0)
    joint_noise: float = 0.05
    door: DoorConfig = field(default_factory=DoorConfig)
    window: WindowConfig = field(default_factory=WindowConfig)
    fridge: FridgeConfig = field(default_factory=FridgeConfig)
    cameras: CameraConfig = field(default_factory=_default_cameras)
    controller: ControllerConfig = field(default_factory=ControllerConfig)

    def __post_init__(self) -> None:
        require_positive(self, "timestep")
        for name, limit in (("position_noise", 0.1), ("yaw_noise", math.radians(30.0)),
                            ("joint_noise", 0.3)):
            value = getattr(self, name)
            require_non_negative(self, name)
            if value > limit:
                raise ConfigError(f"ArticulatedConfig.{name} must be at most {limit:.4g}; "
                                  f"got {value!r}")
        check_world_timing("ArticulatedConfig", self.timestep, self.controller, self.table_min,
                           self.table_max)
        self.grid  # noqa: B018 - validates the workspace box (raises GridError)

    @property
    def grid(self) -> VoxelGrid:
        """The voxel workspace (about 1 cm voxels with the defaults)."""
        return VoxelGrid(self.workspace_min, self.workspace_max, self.grid_shape)

    @property
    def substeps(self) -> int:
        """Physics steps per controller waypoint."""
        return round(self.controller.control_dt / self.timestep)


__all__ = ["HINGE_TRAVEL", "LEVER_TRAVEL", "SASH_TRAVEL", "ArticulatedConfig", "DoorConfig",
           "FridgeConfig", "WindowConfig"]
