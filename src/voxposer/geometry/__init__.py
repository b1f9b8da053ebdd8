"""Base geometry every stage may import (like :mod:`voxposer.errors`; it imports no stage).

* :class:`VoxelGrid` (every world↔voxel conversion), :func:`unit_direction`
* :data:`TOP_DOWN_QUAT`, :func:`pointat2quat`, :func:`wxyz_to_xyzw`, :func:`xyzw_to_wxyz`
"""

from voxposer.geometry.frames import TOP_DOWN_QUAT, pointat2quat, wxyz_to_xyzw, xyzw_to_wxyz
from voxposer.geometry.voxel_grid import VoxelGrid, unit_direction

__all__ = ["TOP_DOWN_QUAT", "VoxelGrid", "pointat2quat", "unit_direction", "wxyz_to_xyzw",
           "xyzw_to_wxyz"]
