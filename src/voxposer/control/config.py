"""Configuration of closed-loop execution (paper Sec. 3.3, Sec. 4 "Motion Planner")."""

from __future__ import annotations

from dataclasses import dataclass, field

from voxposer.config_checks import require_int_at_least, require_positive
from voxposer.errors import ConfigError
from voxposer.planning.planner_config import PlannerConfig
from voxposer.planning.push_primitive import PushConfig
from voxposer.valuemaps.cost import CostMapConfig


def _object_planner() -> PlannerConfig:
    # An object's centre must keep its half-width (blocks: 2.5 cm) away from other objects.
    return PlannerConfig(cost=CostMapConfig(obstacle_margin_cm=3.0, entity_clear_radius_cm=4.0))


@dataclass(frozen=True)
class ExecutorConfig:
    """Closed-loop execution parameters.

    Attributes:
        replan_hz: replanning rate in simulated time [Hz]: after each plan the robot follows the
            trajectory for ``1 / replan_hz`` seconds, then observes and replans (paper: 5 Hz).
        max_time_s: simulated time limit of one ``execute`` call [s].
        reach_tolerance_m: the entity has arrived within this distance of the target [m].
        lookahead_m: the controller is steered toward the trajectory point this far ahead [m].
        stall_replans: give up after this many replans without ``min_progress_m`` of progress.
        min_progress_m: progress that resets the stall counter [m].
        max_pushes: pushes allowed for an object entity before giving up.
        push_reach_m: (near, far): a pushed object's path keeps between these distances
            across the table from the robot's base [m] where that leaves a path: the Panda's
            top-down hand reaches ~0.80 m at push height and stands ~8 cm beyond the object to
            push it back toward the base; within ~0.25 m of the base it is crowded against the
            arm (:func:`~voxposer.control.table_layer.beyond_push_reach`). (0, 0): no limit.
        carry_radius_m: an object whose centre is this close to the closed hand is carried, not
            pushed [m].
        carry_min_opening_m: … if the closed fingers are at least this far apart (closed on
            something) [m].
        hand_floor_m: the bare hand's targets are at least this high above the table's top
            [m]: the finger pads touch it with the grasp centre ~1.4 cm above it, and a hand
            sent to a point on the table (a place named without a height) then drags on it and
            stalls short (0: targets left where they are).
        ee_planner: planner parameters when the end effector is the entity (a straightened
            segment of the hand's path also comes no nearer what it avoids:
            ``shortcut_keeps_distance``).
        object_planner: planner parameters when an object or part is the entity.
        push: random-shooting MPC parameters.
    """

    replan_hz: float = 5.0
    max_time_s: float = 40.0
    reach_tolerance_m: float = 0.02
    lookahead_m: float = 0.04
    stall_replans: int = 15
    min_progress_m: float = 0.005
    max_pushes: int = 25
    push_reach_m: tuple[float, float] = (0.27, 0.72)
    carry_radius_m: float = 0.08
    carry_min_opening_m: float = 0.02
    hand_floor_m: float = 0.02
    ee_planner: PlannerConfig = field(
        default_factory=lambda: PlannerConfig(cost=CostMapConfig(obstacle_margin_cm=1.0),
                                              shortcut_keeps_distance=True)
    )
    object_planner: PlannerConfig = field(default_factory=_object_planner)
    push: PushConfig = field(default_factory=PushConfig)

    def __post_init__(self) -> None:
        require_positive(self, "replan_hz", "max_time_s", "reach_tolerance_m", "lookahead_m",
                         "min_progress_m", "carry_radius_m", "carry_min_opening_m")
        if not (isinstance(self.hand_floor_m, int | float) and 0.0 <= self.hand_floor_m <= 0.2):
            raise ConfigError(f"ExecutorConfig.hand_floor_m must be in [0, 0.2] m; got "
                              f"{self.hand_floor_m!r}")
        require_int_at_least(self, 1, "stall_replans", "max_pushes")
        near_far = self.push_reach_m
        if not (isinstance(near_far, tuple) and len(near_far) == 2
                and all(isinstance(v, int | float) for v in near_far)
                and 0.0 <= near_far[0] <= near_far[1] <= 5.0):
            raise ConfigError(f"ExecutorConfig.push_reach_m must be (near, far) [m] with "
                              f"0 <= near <= far <= 5 ((0, 0): no limit); got {near_far!r}")
