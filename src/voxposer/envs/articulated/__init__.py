"""Articulated scenes for online dynamics learning (paper Sec. 3.4, 4.3, Table 3).

Three tasks, each the Panda (as on the tabletop) and one object on a table, with four RGB-D
cameras: open a latched **door** (press its lever past ``DoorConfig.unlatch_angle``, then pull),
slide a **window** sash sideways, open a **fridge** held shut by a magnetic seal
(``FridgeConfig.seal_force``).

Public API
----------
``ArticulatedWorld(task: str, config: ArticulatedConfig | None = None)``: a
:class:`voxposer.robot.Robot` and observation source
    ``reset(rng) -> ArticulatedPlacement``; ``observe(width=None, height=None, rgb=True) ->
    Observation`` (labels: the object's parts, "table", "robot", "gripper");
    ``step``, ``move_to_pose``, ``open_gripper``, ``close_gripper``, ``reset_to_default_pose``,
    ``get_ee_pose``, ``joint_positions``, ``get_gripper_state``, ``gripper_opening``, ``time``,
    ``control_period``, ``base_position`` (the Robot protocol); ``advance(nsteps)``;
    ``step_callbacks``; ground truth for checks and tests: ``articulation_state()``,
    ``set_articulation_state(values)``, ``part_position(name)``, ``joint_axis(key)``,
    ``success() -> (bool, reason)``
``ArticulatedConfig`` (``DoorConfig``, ``WindowConfig``, ``FridgeConfig``): typed, validated.
``TASKS``: task name → object class; ``make_object(task, config)``.
"""

import os

os.environ.setdefault("MUJOCO_GL", "egl")

from voxposer.envs.articulated.articulated_object import ArticulatedObject, JointAxis
from voxposer.envs.articulated.config import (
    ArticulatedConfig,
    DoorConfig,
    FridgeConfig,
    WindowConfig,
)
from voxposer.envs.articulated.scene import TASKS, make_object
from voxposer.envs.articulated.world import ArticulatedPlacement, ArticulatedWorld

__all__ = [
    "TASKS",
    "ArticulatedConfig",
    "ArticulatedObject",
    "ArticulatedPlacement",
    "ArticulatedWorld",
    "DoorConfig",
    "FridgeConfig",
    "JointAxis",
    "WindowConfig",
    "make_object",
]
