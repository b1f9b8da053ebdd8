"""Voxel workspace, value maps (paper App. A.3) and the planner's cost map."""

from voxposer.valuemaps.cost import CostMap, CostMapConfig, compose_cost_map
from voxposer.valuemaps.grid import VoxelGrid, unit_direction
from voxposer.valuemaps.maps import (
    MAP_KINDS,
    TOP_DOWN_QUAT,
    ValueMapAPI,
    check_value_map,
    pointat2quat,
)

__all__ = [
    "MAP_KINDS",
    "TOP_DOWN_QUAT",
    "CostMap",
    "CostMapConfig",
    "ValueMapAPI",
    "VoxelGrid",
    "check_value_map",
    "compose_cost_map",
    "pointat2quat",
    "unit_direction",
]
