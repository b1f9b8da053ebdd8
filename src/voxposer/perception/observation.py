"""What a robot's cameras and joints report at one instant: per-camera RGB-D views and its state.

Camera conventions of :class:`CameraFrame` (OpenCV): x right, y down, z forward (the viewing
direction). ``intrinsics`` K maps camera-frame points to pixels ``(u, v) = (fx x/z + cx,
fy y/z + cy)`` with integer pixel centres (column u, row v, row 0 at the top of the image), and
``extrinsics`` is the 4x4 camera-to-world transform.

Producers (the simulator, a real camera driver) fill these; perception fuses and segments them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class CameraFrame:
    """One camera's view.

    Attributes:
        name: camera name (e.g. ``"front_left"``).
        rgb: colour image, shape (H, W, 3), uint8 (black when colour was not rendered).
        depth: depth along the optical axis [m], shape (H, W), float32; ``inf`` for background.
        intrinsics: K, shape (3, 3).
        extrinsics: camera-to-world transform, shape (4, 4) (OpenCV camera axes).
        object_ids: segmentation channel: object label per pixel (an index into the
            observation's ``label_names``), shape (H, W), int32; -1 where no object. In
            simulation this is ground truth; a camera without segmentation leaves it all -1.
    """

    name: str
    rgb: NDArray[np.uint8]
    depth: NDArray[np.float32]
    intrinsics: NDArray[np.float64]
    extrinsics: NDArray[np.float64]
    object_ids: NDArray[np.int32]


@dataclass(frozen=True)
class Observation:
    """One observation: every camera's view and the robot's state at ``time``.

    Attributes:
        time: time of the observation [s] (simulated time in simulation).
        cameras: the RGB-D views, one per camera.
        ee_position: end-effector position [m], shape (3,).
        ee_quat: end-effector orientation, scalar-last (x, y, z, w).
        gripper: commanded gripper state, 1.0 closed, 0.0 open.
        label_names: name of each segmentation label, indexable by the ids in
            ``cameras[i].object_ids``.
    """

    time: float
    cameras: tuple[CameraFrame, ...]
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
