"""The registry of the paper's 13 simulated tasks (Table 4), in Table 4's row order.

``get_task(name)`` returns a task; unknown names raise ConfigError listing the known ones.
"""

from __future__ import annotations

from typing import Final

from voxposer.bench.task import BenchTask
from voxposer.bench.tasks.close_drawer import CloseDrawer
from voxposer.bench.tasks.drop_to_pos import DropToPos
from voxposer.bench.tasks.grasp_at_velocity import GraspAtVelocity
from voxposer.bench.tasks.min_distance import MinDistance
from voxposer.bench.tasks.move_to_preposition import MoveToPreposition
from voxposer.bench.tasks.move_to_region import MoveToRegion
from voxposer.bench.tasks.push_along_line import PushAlongLine
from voxposer.bench.tasks.push_avoid_obstacle import PushAvoidObstacle
from voxposer.bench.tasks.push_stay_on_region import PushStayOnRegion
from voxposer.bench.tasks.push_to_pos import PushToPos
from voxposer.bench.tasks.staying_on_preposition import StayingOnPreposition
from voxposer.bench.tasks.velocity_in_region import VelocityInRegion
from voxposer.bench.tasks.velocity_near_obj import VelocityNearObj
from voxposer.errors import ConfigError

#: task name → task, in the row order of the paper's Table 4.
TASKS: Final[dict[str, BenchTask]] = {
    t.name: t
    for t in (
        MoveToPreposition(),
        StayingOnPreposition(),
        VelocityNearObj(),
        CloseDrawer(),
        PushAlongLine(),
        GraspAtVelocity(),
        DropToPos(),
        PushStayOnRegion(),
        MoveToRegion(),
        MinDistance(),
        VelocityInRegion(),
        PushAvoidObstacle(),
        PushToPos(),
    )
}


def get_task(name: str) -> BenchTask:
    """The task called ``name``; raises ConfigError listing the known tasks."""
    if name not in TASKS:
        raise ConfigError(f"unknown task {name!r}; tasks are: {', '.join(TASKS)}")
    return TASKS[name]


__all__ = ["TASKS", "get_task"]
