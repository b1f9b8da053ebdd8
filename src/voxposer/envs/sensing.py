"""The world's read-only side: camera views, robot state, and ground truth for checks.

A mixin of :class:`voxposer.envs.world.TabletopWorld`; split out so that physics/control and
observation each stay one concept. Observations are cached until the physics state changes, so
several perception queries at one instant render the cameras once. The world produces views with
a ground-truth segmentation channel; detecting objects in them is perception's job
(:class:`voxposer.perception.segmentation.SegmentationPerceiver`).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from voxposer.catalog import OBJECTS
from voxposer.envs.arm import ArmStateMixin
from voxposer.envs.cameras import CameraRenderer
from voxposer.envs.config import WorldConfig
from voxposer.envs.registry import ObjectRegistry
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.observation import Observation


class SensingMixin(ArmStateMixin):
    """Observation and ground-truth queries (needs the attributes declared below; the robot's
    state queries come from :class:`~voxposer.envs.arm.ArmStateMixin`)."""

    config: WorldConfig
    grid: VoxelGrid
    model: mujoco.MjModel
    data: mujoco.MjData
    registry: ObjectRegistry
    _renderer: CameraRenderer | None
    _obs: Observation | None
    _obs_key: tuple[float, int, int, bool] | None
    _present: tuple[str, ...]
    _gripper: float

    # ----------------------------------------------------------------- names
    @property
    def object_names(self) -> tuple[str, ...]:
        """Canonical names of the objects in the current scene."""
        return self._present

    @property
    def camera_names(self) -> tuple[str, ...]:
        """The cameras, e.g. ``("front_left", "front_right", "back_left", "back_right")``."""
        return self.config.cameras.names

    # ------------------------------------------------------------ rendering
    def _camera_renderer(self) -> CameraRenderer:
        if self._renderer is None:
            cams = self.config.cameras
            self._renderer = CameraRenderer(self.model, self.registry.geom_labels,
                                            shadows=cams.shadows, depth_max=cams.depth_max,
                                            detailed_robot=cams.detailed_robot)
        return self._renderer

    def render(self, camera: str, width: int | None = None, height: int | None = None
               ) -> NDArray[np.uint8]:
        """RGB image, shape (height, width, 3), of ``camera`` (e.g. ``"front_left"``)."""
        cams = self.config.cameras
        frame = self._camera_renderer().render(
            self.data, f"{camera.removesuffix('_camera')}_camera", width or cams.width,
            height or cams.height, segmentation=False)
        return frame.rgb

    def observe(self, width: int | None = None, height: int | None = None, *,
                rgb: bool = True) -> Observation:
        """All camera views (RGB, depth [m], intrinsics, extrinsics, ground-truth object ids)
        and the robot's state. Cached until the state changes.

        ``rgb=False`` skips the colour pass (images are black): enough for planning and
        detection, about half the rendering time. An RGB observation also serves
        later ``rgb=False`` requests at the same instant.
        """
        cams = self.config.cameras
        w, h = width or cams.width, height or cams.height
        key = (float(self.data.time), w, h)
        if self._obs is not None and self._obs_key is not None and self._obs_key[:3] == key and (
                self._obs_key[3] or not rgb):
            return self._obs
        renderer = self._camera_renderer()
        frames = tuple(renderer.render(self.data, f"{name}_camera", w, h, colour=rgb)
                       for name in cams.names)
        pos, quat = self.get_ee_pose()
        self._obs = Observation(
            time=float(self.data.time),
            cameras=frames,
            ee_position=pos,
            ee_quat=quat,
            gripper=self._gripper,
            label_names=tuple(o.name for o in OBJECTS),
        )
        self._obs_key = (*key, rgb)
        return self._obs

    def close(self) -> None:
        """Release the rendering context (the world stays usable; rendering reopens it)."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    # ------------------------------------------------------- ground truth
    def object_position(self, name: str) -> NDArray[np.float64]:
        """Simulator ground-truth position [m] of an object's root body (for success checks)."""
        self.registry.resolve(name, self._present)
        return self.data.xpos[self.model.body(self.registry.body(name)).id].copy()

    def object_yaw(self, name: str) -> float:
        """Simulator ground-truth yaw [rad] of an object's root body about world z."""
        self.registry.resolve(name, self._present)
        mat = self.data.xmat[self.model.body(self.registry.body(name)).id].reshape(3, 3)
        return math.atan2(mat[1, 0], mat[0, 0])

    def drawer_axis(self, drawer: str) -> NDArray[np.float64]:
        """Simulator ground truth: the unit world direction, shape (3,), in which ``drawer``
        ("top" or "top drawer") opens (for checks and tests; the executor gets the direction
        from perception)."""
        which = drawer.lower().removesuffix(" drawer").strip()
        obj = self.registry.resolve(f"{which} drawer", self._present)
        joint = self.model.joint(f"{self.registry.body(obj.name)}_joint")
        parent = self.model.jnt_bodyid[joint.id]
        axis = self.data.xmat[parent].reshape(3, 3) @ self.model.jnt_axis[joint.id]
        return np.asarray(axis / np.linalg.norm(axis), dtype=np.float64)

    def drawer_opening(self, drawer: str) -> float:
        """How far a drawer ("top", "middle", "bottom" or "top drawer") is open [m]."""
        which = drawer.lower().removesuffix(" drawer").strip()
        obj = self.registry.resolve(f"{which} drawer", self._present)
        joint = self.model.joint(f"{self.registry.body(obj.name)}_joint")
        return float(self.data.qpos[joint.qposadr[0]])
