"""What the world returns when it looks at itself: camera views, fused cloud, robot state."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from voxposer.envs.cameras import CameraFrame
from voxposer.perception.point_cloud import PointCloud


@dataclass(frozen=True)
class Observation:
    """One observation of the tabletop world.

    Attributes:
        time: simulation time [s].
        cameras: the RGB-D views, one per camera.
        cloud: fused world-frame point cloud of all views, cropped to the workspace, with
            per-point object labels and normals.
        ee_position: end-effector position [m], shape (3,).
        ee_quat: end-effector orientation, scalar-last (x, y, z, w).
        gripper: commanded gripper state, 1.0 closed, 0.0 open.
        label_names: name of each object label, indexable by the ids in ``cloud.labels`` and
            ``cameras[i].object_ids``.
    """

    time: float
    cameras: tuple[CameraFrame, ...]
    cloud: PointCloud
    ee_position: NDArray[np.float64]
    ee_quat: NDArray[np.float64]
    gripper: float
    label_names: tuple[str, ...]

    def camera(self, name: str) -> CameraFrame:
        """The view of camera ``name`` (e.g. ``"front_left"``)."""
        for frame in self.cameras:
            if frame.name == name:
                return frame
        raise KeyError(f"no camera {name!r}; cameras are: {[f.name for f in self.cameras]}")
