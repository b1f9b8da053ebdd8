"""The simulated tabletop world of the paper (App. A.5) in MuJoCo.

World frame: metres, right-handed, z up; front = +x, right = +y. The table top is z = 0 and the
Franka Panda stands at the back (−x) facing +x. Public quaternions are scalar-last (x, y, z, w);
the end-effector's approach axis is its local +z (top-down: :data:`TOP_DOWN_QUAT`).

Public API
----------
``TabletopWorld(config: WorldConfig | None = None)``
    ``reset(rng: np.random.Generator, layout: SceneLayout | None = None) -> Placement``
    ``observe(width=None, height=None, rgb=True) -> Observation`` (4 RGB-D views with a
    ground-truth segmentation channel, robot state); objects are found in them by perception
    (``SegmentationPerceiver(world, world.grid).detect(name)``)
    ``step(position, quat_xyzw, gripper=None, speed_scale=1.0) -> StepResult`` (one waypoint)
    ``move_to_pose(position, quat_xyzw=None, speed_scale=1.0, gripper=None) -> MoveResult``
    (raises ``UnreachablePoseError`` with the closest reachable error, ``InvalidActionError``)
    ``open_gripper()``, ``close_gripper()``, ``reset_to_default_pose(speed_scale=1.0)``
    ``get_ee_pose() -> (position (3,), quat_xyzw (4,))``, ``get_gripper_state() -> float``
    (1 closed, 0 open), ``gripper_opening() -> float`` [m], ``joint_positions()``,
    ``control_period``, ``time``, ``base_position``: the :class:`voxposer.robot.Robot` protocol
    ``object_names``, ``camera_names``, ``grid`` (the workspace ``VoxelGrid``), ``config``
    ``render(camera, width=None, height=None) -> (H, W, 3) uint8``
    ``object_position(name)``, ``object_yaw(name)``, ``drawer_opening(drawer)`` (ground truth)
    ``push_robot(rng, ...)``, ``displace_object(rng, name=None, ...)``,
    ``revert_progress(rng, drawer=None, ...)`` → ``Disturbance`` records
    ``advance(nsteps)`` (raw physics; raises ``SimulationUnstableError``), ``close()``
``WorldConfig``, ``CameraConfig``, ``ControllerConfig``: typed, validated configuration.
``SceneLayout``: which blocks/lines must be present, distractor counts, cabinet, drawer
openings, hand-placed poses. ``Placement``: what a reset chose.
``TabletopEnv``: Gymnasium wrapper (action: position 3, quaternion xyzw 4, gripper 1).
``render_views(seed, out, ...)``: the four views of a seeded scene tiled into one PNG
(CLI: :mod:`voxposer.cli.render` with ``add_parser(subparsers)`` and ``run(args)``).
``OBJECTS``: the catalog of nameable objects (:mod:`voxposer.catalog`).

Rendering is offscreen through EGL unless ``MUJOCO_GL`` says otherwise.
"""

import os

os.environ.setdefault("MUJOCO_GL", "egl")

from voxposer.catalog import DRAWERS, OBJECTS, SceneObject
from voxposer.envs.config import (
    COLORS,
    CameraConfig,
    ControllerConfig,
    WorldConfig,
)
from voxposer.envs.disturbances import Disturbance
from voxposer.envs.gym_env import TabletopEnv
from voxposer.envs.layout import Placement, SceneLayout
from voxposer.envs.picture import render_views
from voxposer.envs.world import TOP_DOWN_QUAT, MoveResult, StepResult, TabletopWorld

__all__ = [
    "COLORS",
    "DRAWERS",
    "OBJECTS",
    "TOP_DOWN_QUAT",
    "CameraConfig",
    "ControllerConfig",
    "Disturbance",
    "MoveResult",
    "Placement",
    "SceneLayout",
    "SceneObject",
    "StepResult",
    "TabletopEnv",
    "TabletopWorld",
    "WorldConfig",
    "render_views",
]
