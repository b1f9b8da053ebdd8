"""Perception: fused labelled point clouds with normals, and ``detect`` on top of them.

Public API:

* :class:`PointCloud`, :func:`fuse_views`, :func:`backproject`, :func:`camera_normals`
* :class:`DetectedObject` (a frozen dataclass that also reads like a dict), :func:`detect_in_cloud`
"""

from voxposer.perception.detect import DetectedObject, detect_in_cloud
from voxposer.perception.point_cloud import (
    PointCloud,
    backproject,
    camera_normals,
    fuse_views,
)

__all__ = [
    "DetectedObject",
    "PointCloud",
    "backproject",
    "camera_normals",
    "detect_in_cloud",
    "fuse_views",
]
