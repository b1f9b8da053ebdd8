"""The world's read-only side: camera views, robot state, and ground truth for checks.

A mixin of :class:`voxposer.envs.world.TabletopWorld`; split out so that physics/control and
observation each stay one concept. Observations are cached until the physics state changes, so
several perception queries at one instant render the cameras once. The world produces views with
a ground-truth segmentation channel; detecting objects in them is perception's job
(:class:`voxposer.perception.segmentation.SegmentationPerceiver`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from voxposer.catalog import OBJECTS
from voxposer.envs.config import WorldConfig
from voxposer.envs.registry import ObjectRegistry
from voxposer.envs.views import CameraViewsMixin
from voxposer.geometry.voxel_grid import VoxelGrid

#: the segmentation channel's names: every catalog object, in catalog order
_CATALOG_NAMES = tuple(o.name for o in OBJECTS)


class SensingMixin(CameraViewsMixin):
    """Observation and ground-truth queries (needs the attributes declared below; rendering and
    observations come from :class:`~voxposer.envs.views.CameraViewsMixin`, the robot's state
    queries from :class:`~voxposer.envs.arm.ArmStateMixin`)."""

    config: WorldConfig
    grid: VoxelGrid
    registry: ObjectRegistry
    _present: tuple[str, ...]

    # ----------------------------------------------------------------- names
    @property
    def object_names(self) -> tuple[str, ...]:
        """Canonical names of the objects in the current scene."""
        return self._present

    def _geom_label_ids(self) -> NDArray[np.int32]:
        return self.registry.geom_labels

    def _label_names(self) -> tuple[str, ...]:
        return _CATALOG_NAMES

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
