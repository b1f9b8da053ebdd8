"""The observation vector o_t of online dynamics learning, and how it is read off perception.

o_t = [end-effector position (3) [m], gripper command (1), handle position (3) [m], the
object's observed state (task-dependent: handle angle and door angle [rad], or the window's
offset [m])]. Everything but the robot's own state comes from perception
(:class:`voxposer.perception.articulation.ArticulationEstimator`), never from the simulator's
joints.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.perception.articulation import ArticulationEstimator, ArticulationParts
from voxposer.perception.perceiver import Perceiver
from voxposer.robot import Robot


@dataclass(frozen=True)
class StateLayout:
    """Where each quantity sits in an observation vector.

    Attributes:
        task: the articulated task.
        parts: the parts perception reads (handle, hinged or sliding part, lever).
        state_names: the object-state entries after the handle position, in order.
    """

    task: str
    parts: ArticulationParts
    state_names: tuple[str, ...]

    @property
    def dim(self) -> int:
        """D_o, the observation's length."""
        return 7 + len(self.state_names)

    @property
    def names(self) -> tuple[str, ...]:
        """A name per entry (for logs and reports)."""
        return ("ee_x", "ee_y", "ee_z", "gripper", "handle_x", "handle_y", "handle_z",
                *self.state_names)

    def entity_slice(self, entity: str) -> slice:
        """The 3 entries holding ``entity``'s position: the end effector for "gripper" (and
        "robot"), the handle for any part of the object.

        Raises:
            ConfigError: ``entity`` is neither.
        """
        if entity in ("gripper", "robot", "end effector"):
            return slice(0, 3)
        if entity in self.parts.names:
            return slice(4, 7)
        raise ConfigError(f"entity {entity!r} is not observed in the {self.task} task; "
                          f"observed: gripper, {', '.join(self.parts.names)}")

    def index(self, name: str) -> int:
        """The entry called ``name`` (see :attr:`names`)."""
        if name not in self.names:
            raise ConfigError(f"no observation entry {name!r}; entries: {', '.join(self.names)}")
        return self.names.index(name)


#: The observation layout of each articulated task.
LAYOUTS: Final[dict[str, StateLayout]] = {
    "door": StateLayout("door", ArticulationParts(handle="door handle", hinged="door",
                                                  lever="door handle"),
                        ("handle_angle", "door_angle")),
    "window": StateLayout("window", ArticulationParts(handle="window handle", sliding="window"),
                          ("window_offset",)),
    "fridge": StateLayout("fridge", ArticulationParts(handle="fridge handle",
                                                      hinged="fridge door"),
                          ("door_angle",)),
}


def layout_for(task: str) -> StateLayout:
    """The layout of ``task``; ConfigError listing the tasks for an unknown one."""
    if task not in LAYOUTS:
        raise ConfigError(f"unknown articulated task {task!r}; tasks are: {', '.join(LAYOUTS)}")
    return LAYOUTS[task]


class StateObserver:
    """Reads o_t from a robot and a perceiver; call :meth:`reset` after every scene reset."""

    def __init__(self, layout: StateLayout, robot: Robot, perceiver: Perceiver) -> None:
        self.layout = layout
        self.robot = robot
        self.estimator = ArticulationEstimator(perceiver, layout.parts)

    def reset(self) -> None:
        """Take the closed object's reference (hinge direction, sliding part's place)."""
        self.estimator.reset()

    def observe(self) -> NDArray[np.float64]:
        """o_t, shape (D_o,)."""
        ee, _ = self.robot.get_ee_pose()
        state = self.estimator.estimate()
        values = [state[name] for name in self.layout.state_names]
        return np.concatenate([ee, [self.robot.get_gripper_state()], state["handle_position"],
                               values]).astype(np.float64)


__all__ = ["LAYOUTS", "StateLayout", "StateObserver", "layout_for"]
