"""The perception seam: what the programs and the executor ask of perception.

A :class:`Perceiver` turns the latest observation into objects (``detect``), obstacles
(``scene_occupancy``) and the motion direction of sliding parts. The simulator's ground-truth
segmentation is one implementation (:class:`voxposer.perception.segmentation.SegmentationPerceiver`);
an open-vocabulary detector on a real camera is another. Nothing downstream knows which.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.detect import DetectedObject
from voxposer.perception.observation import Observation
from voxposer.perception.point_cloud import PointCloud


@runtime_checkable
class ObservationSource(Protocol):
    """Something that observes the scene: the simulator, or a driver of real cameras."""

    @property
    def object_names(self) -> tuple[str, ...]:
        """Canonical names of the objects in the scene (what may be detected)."""
        ...

    def observe(self, *, rgb: bool = True, labels: bool = True) -> Observation:
        """The current views and robot state (``rgb=False``: colour may be skipped;
        ``labels=False``: a simulator's ground-truth label ids may be skipped)."""
        ...


@runtime_checkable
class Perceiver(Protocol):
    """Objects, obstacles and sliding directions from the latest observation (world frame, m)."""

    @property
    def grid(self) -> VoxelGrid:
        """The workspace grid occupancies are expressed on."""
        ...

    @property
    def object_names(self) -> tuple[str, ...]:
        """Canonical names of the objects ``detect`` accepts."""
        ...

    def observe(self) -> Observation:
        """The latest observation (taken now if the scene changed since the last one)."""
        ...

    def point_cloud(self) -> PointCloud:
        """The fused, workspace-cropped, labelled cloud of :meth:`observe`."""
        ...

    def detect(self, name: str) -> DetectedObject:
        """Object ``name`` (free-form: "the Grey cube"); raises ``UnknownObjectError`` listing the
        scene's objects, or ``ObjectNotVisibleError``."""
        ...

    def scene_occupancy(self, entity: str, *, holding: bool, ignore_table: bool = False
                        ) -> NDArray[np.bool_]:
        """Obstacle voxels, shape ``grid.shape``, for moving ``entity`` (see
        :func:`voxposer.perception.scene_occupancy.scene_occupancy`)."""
        ...

    def sliding_axis(self, name: str) -> NDArray[np.float64] | None:
        """Unit world direction, shape (3,), in which a sliding part (a drawer, its handle)
        moves when pulled; None for objects that move freely or not at all."""
        ...
