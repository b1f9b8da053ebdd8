"""Typed configuration of the tabletop world, with the paper's setup (App. A.5) as defaults.

World frame: metres, right-handed, z up; front = +x, right = +y. The table top is the plane
z = 0; the robot base stands at the back (−x) of the table facing +x.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Final

from voxposer import tabletop
from voxposer.catalog import COLOR_NAMES
from voxposer.config_checks import require_int_at_least, require_positive
from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid

#: RGBA of each of the paper's ten colours (App. A.5), in the catalog's label order.
COLORS: Final[dict[str, tuple[float, float, float, float]]] = dict(zip(COLOR_NAMES, (
    (0.12, 0.30, 0.85, 1.0),
    (0.15, 0.65, 0.20, 1.0),
    (0.95, 0.85, 0.10, 1.0),
    (0.98, 0.55, 0.75, 1.0),
    (0.50, 0.30, 0.12, 1.0),
    (0.85, 0.10, 0.10, 1.0),
    (1.00, 0.50, 0.05, 1.0),
    (0.50, 0.15, 0.70, 1.0),
    (0.10, 0.85, 0.90, 1.0),
    (0.50, 0.50, 0.50, 1.0),
), strict=True))


@dataclass(frozen=True)
class CameraConfig:
    """The four RGB-D cameras at the corners of the table, aimed at the workspace centre.

    Attributes:
        width, height: image size [pixels].
        fovy: vertical field of view [deg].
        target: the point every camera looks at [m], shape (3,).
        positions: camera name → position [m]; the paper uses four cameras.
        shadows: render shadows (about 10x slower on a CPU renderer).
        antialias: multisample anti-aliasing (4 samples) when True.
        depth_max: depths beyond this [m] are treated as background.
        detailed_robot: draw the robot with its high-poly visual meshes (135k triangles, about
            4x slower on a CPU renderer) instead of its low-poly collision meshes.
        frame_hz: each camera's frame rate in simulated time [Hz], as a real camera streams at
            its own rate: an observation holds each camera's latest frame, the cameras' frames
            spread evenly over one period (at 2.5 Hz and 5 Hz replanning, two of the four views
            are new at each replan); what changes between frames (a disturbance too) shows
            in each view at its next frame. None: every camera renders a new frame at every
            observation.
    """

    width: int = 320
    height: int = 240
    fovy: float = 50.0
    target: tuple[float, float, float] = (-0.15, 0.0, 0.05)
    positions: tuple[tuple[str, tuple[float, float, float]], ...] = (
        ("front_left", (0.42, -0.52, 0.70)),
        ("front_right", (0.42, 0.52, 0.70)),
        ("back_left", (-0.55, -0.72, 0.78)),
        ("back_right", (-0.55, 0.72, 0.78)),
    )
    shadows: bool = False
    antialias: bool = False
    depth_max: float = 4.0
    detailed_robot: bool = False
    frame_hz: float | None = None

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            value = getattr(self, name)
            if not isinstance(value, int) or not 16 <= value <= 4096:
                raise ConfigError(f"CameraConfig.{name} must be an int in [16, 4096]; got {value!r}")
        if not (isinstance(self.fovy, int | float) and 1.0 <= self.fovy <= 170.0):
            raise ConfigError(f"CameraConfig.fovy must be in [1, 170] degrees; got {self.fovy!r}")
        require_positive(self, "depth_max")
        if self.frame_hz is not None:
            require_positive(self, "frame_hz")
        if not self.positions:
            raise ConfigError("CameraConfig.positions must name at least one camera; got none")
        names = [n for n, _ in self.positions]
        if len(set(names)) != len(names):
            raise ConfigError(f"CameraConfig.positions has duplicate camera names: {names}")

    @property
    def names(self) -> tuple[str, ...]:
        """Camera names in order."""
        return tuple(n for n, _ in self.positions)


@dataclass(frozen=True)
class ControllerConfig:
    """End-effector pose controller (App. A.5): IK → interpolated joint waypoints → joint servo.

    Attributes:
        control_dt: period of one waypoint [s] (physics steps ``control_dt / timestep`` times).
        ee_speed: end-effector linear speed at ``speed_scale=1`` [m/s].
        ee_angular_speed: end-effector angular speed at ``speed_scale=1`` [rad/s].
        max_joint_speed: cap on every arm joint's commanded speed at ``speed_scale=1`` [rad/s].
        max_speed_scale: largest accepted ``speed_scale``.
        position_tolerance: IK/arrival position tolerance [m].
        rotation_tolerance: IK/arrival orientation tolerance [rad].
        ik_iterations: IK iterations for a one-off solve.
        ik_restarts: random restarts (from the world's Generator) when a warm start fails.
        settle_time: longest wait for the arm to arrive after the reference reached the goal [s].
        gripper_time: time given to the fingers to open or close [s].
    """

    control_dt: float = 0.02
    ee_speed: float = 0.25
    ee_angular_speed: float = 1.2
    max_joint_speed: float = 1.5
    max_speed_scale: float = 5.0
    position_tolerance: float = 0.005
    rotation_tolerance: float = 0.035
    ik_iterations: int = 40
    ik_restarts: int = 12
    settle_time: float = 1.0
    gripper_time: float = 0.4

    def __post_init__(self) -> None:
        require_positive(self, "control_dt", "ee_speed", "ee_angular_speed", "max_joint_speed",
                         "max_speed_scale", "position_tolerance", "rotation_tolerance",
                         "settle_time", "gripper_time")
        require_int_at_least(self, 1, "ik_iterations")
        require_int_at_least(self, 0, "ik_restarts")


def check_world_timing(owner: str, timestep: float, controller: ControllerConfig,
                       table_min: tuple[float, float], table_max: tuple[float, float]) -> None:
    """Check a world config's physics step [s] (at most 0.01 s, dividing the controller period)
    and its table rectangle [m]; ``owner`` names the config class in the messages.

    Raises:
        ConfigError: naming the field and the bad value.
    """
    if timestep > 0.01:
        raise ConfigError(f"{owner}.timestep must be <= 0.01 s; got {timestep!r}")
    steps = controller.control_dt / timestep
    if abs(steps - round(steps)) > 1e-6 or round(steps) < 1:
        raise ConfigError(
            f"ControllerConfig.control_dt ({controller.control_dt}) must be a whole "
            f"multiple of {owner}.timestep ({timestep})"
        )
    if any(lo >= hi for lo, hi in zip(table_min, table_max, strict=True)):
        raise ConfigError(f"{owner}.table_min {table_min} must be below table_max {table_max}")


@dataclass(frozen=True)
class WorldConfig:
    """The tabletop world: table, robot placement, objects, physics and workspace grid.

    Defaults are the one layout description, :mod:`voxposer.tabletop`.

    Attributes:
        timestep: physics step [s].
        table_min, table_max: table top extent in x, y [m]; the top surface is z = 0.
        robot_base: position of the robot base [m] (back of the table, facing +x).
        block_size: edge of the cube blocks [m]; block_mass [kg]; block_friction (sliding).
        line_length, line_width: size of the thin coloured lines on the table [m].
        cabinet_position: x, y of the cabinet centre [m]; its drawers open toward −y.
        workspace_min, workspace_max: the voxel workspace box [m]; grid_shape: voxels per axis.
        cameras, controller: nested configs.
    """

    timestep: float = 0.002
    table_min: tuple[float, float] = tabletop.TABLE_MIN
    table_max: tuple[float, float] = tabletop.TABLE_MAX
    robot_base: tuple[float, float, float] = tabletop.ROBOT_BASE
    block_size: float = tabletop.BLOCK_SIZE
    block_mass: float = 0.1
    block_friction: float = 1.0
    line_length: float = tabletop.LINE_LENGTH
    line_width: float = tabletop.LINE_WIDTH
    cabinet_position: tuple[float, float] = tabletop.CABINET_POSITION
    workspace_min: tuple[float, float, float] = tabletop.WORKSPACE_MIN
    workspace_max: tuple[float, float, float] = tabletop.WORKSPACE_MAX
    grid_shape: tuple[int, int, int] = tabletop.GRID_SHAPE
    cameras: CameraConfig = field(default_factory=CameraConfig)
    controller: ControllerConfig = field(default_factory=ControllerConfig)

    def __post_init__(self) -> None:
        require_positive(self, "timestep", "block_size", "block_mass", "block_friction",
                         "line_length", "line_width")
        check_world_timing("WorldConfig", self.timestep, self.controller, self.table_min,
                           self.table_max)
        self.grid  # noqa: B018 - validates the workspace box (raises GridError)

    @property
    def grid(self) -> VoxelGrid:
        """The voxel workspace over the table (about 1 cm voxels with the defaults)."""
        return VoxelGrid(self.workspace_min, self.workspace_max, self.grid_shape)

    @property
    def substeps(self) -> int:
        """Physics steps per controller waypoint."""
        return round(self.controller.control_dt / self.timestep)
