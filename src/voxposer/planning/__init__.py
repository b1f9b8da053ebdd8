"""Motion planning over value maps: global path search, smoothing, 6-DoF trajectories."""

from voxposer.planning.planner import PathPlanner, Plan
from voxposer.planning.planner_config import PlannerConfig
from voxposer.planning.search import SearchResult, astar, greedy_descent
from voxposer.planning.trajectory import Trajectory, Waypoint

__all__ = [
    "PathPlanner",
    "Plan",
    "PlannerConfig",
    "SearchResult",
    "Trajectory",
    "Waypoint",
    "astar",
    "greedy_descent",
]
