"""Value maps (paper App. A.3) and the planner's cost map.

``VoxelGrid``, ``TOP_DOWN_QUAT`` and ``pointat2quat`` are re-exported from the base module
:mod:`voxposer.geometry`, where they live.
"""

from voxposer.geometry import TOP_DOWN_QUAT, VoxelGrid, pointat2quat, unit_direction
from voxposer.valuemaps.cost import CostMap, CostMapConfig, compose_cost_map
from voxposer.valuemaps.maps import MAP_KINDS, ValueMapAPI, check_value_map

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
