"""Perception from a segmentation channel: the simulator's ground truth, as in the paper's
simulated setup (App. A.5). All geometry comes from the fused depth, not from body poses.

Each call works on the latest observation of an :class:`ObservationSource`; the fused cloud is
computed once per observation, so several ``detect`` calls at one instant fuse once.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from voxposer import catalog
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.detect import DetectedObject, detect_in_cloud
from voxposer.perception.names import match_name
from voxposer.perception.observation import Observation
from voxposer.perception.occlusion_memory import REMEMBERED_KINDS, OcclusionMemory
from voxposer.perception.perceiver import ObservationSource
from voxposer.perception.point_cloud import DepthView, PointCloud, fuse_views
from voxposer.perception.scene_occupancy import scene_occupancy
from voxposer.perception.sliding_axis import drawer_front_normal


class SegmentationPerceiver:
    """A :class:`~voxposer.perception.perceiver.Perceiver` reading object labels from the views'
    segmentation channel (``CameraFrame.object_ids``).

    Args:
        source: what observes the scene (e.g. :class:`voxposer.envs.TabletopWorld`).
        grid: the workspace grid; the fused cloud is cropped to it.
    """

    def __init__(self, source: ObservationSource, grid: VoxelGrid) -> None:
        self.source = source
        self._grid = grid
        self._obs: Observation | None = None
        self._cloud: PointCloud | None = None
        #: detections of the current observation, by canonical name (their arrays are
        #: read-only, so callers share them); emptied when a new observation arrives
        self._detections: dict[str, DetectedObject] = {}
        #: each camera's last view and its points (a view not renewed is not lifted again)
        self._views: dict[int, tuple[DepthView, PointCloud]] = {}
        #: the parts of blocks and lines other objects hide now (a block on a line's end)
        self._memory = OcclusionMemory()

    @property
    def grid(self) -> VoxelGrid:
        return self._grid

    @property
    def object_names(self) -> tuple[str, ...]:
        return tuple(self.source.object_names)

    def observe(self) -> Observation:
        obs = self.source.observe(rgb=False)
        if obs is not self._obs:
            self._obs, self._cloud, self._detections = obs, None, {}
        return obs

    def point_cloud(self) -> PointCloud:
        obs = self.observe()
        if self._cloud is None:
            self._cloud = fuse_views(obs.cameras, self._grid, self._views)
        return self._cloud

    def detect(self, name: str) -> DetectedObject:
        """Find ``name`` ("blue block", "the top drawer's handle"…) in the fused cloud.

        Raises:
            UnknownObjectError: the name matches no object of the scene (lists them).
            ObjectNotVisibleError: the object is present but no camera sees it.
        """
        canonical = match_name(name, self.object_names)
        cloud = self.point_cloud()
        if canonical in self._detections:  # once per observation (the maps and the executor
            return self._detections[canonical]  # ask for the same objects at every replan)
        names = self.observe().label_names
        known = canonical in names and _in_catalog(canonical)  # other scenes: parts stand alone
        members = set(catalog.family(canonical)) if known else {canonical}
        labels = np.asarray([k for k, n in enumerate(names) if n in members], dtype=np.int32)
        kind = catalog.object_named(canonical).kind if known else None
        sliding = kind in catalog.SLIDING_KINDS
        found = detect_in_cloud(cloud, labels, canonical, self._grid, horizontal_normal=sliding)
        if kind in REMEMBERED_KINDS:
            obs = self.observe()
            found = self._memory.extend(found, obs.cameras, self._grid, obs.time)
        self._detections[canonical] = found
        return found

    def scene_occupancy(self, entity: str, *, holding: bool, ignore_table: bool = False
                        ) -> NDArray[np.bool_]:
        obs = self.observe()
        return scene_occupancy(self.point_cloud(), obs.label_names, obs.ee_position, self._grid,
                               entity=entity, holding=holding, ignore_table=ignore_table)

    def sliding_axis(self, name: str) -> NDArray[np.float64] | None:
        """The outward normal of the sliding part's front, seen by the cameras: a drawer (or
        the drawer of a handle) is pulled out along the normal of its front face. The front is
        the dominant direction among the drawer's sideways-facing normals on its handle's side
        (:func:`~voxposer.perception.sliding_axis.drawer_front_normal`; its side walls,
        visible once it is open, face 90° away and are left out)."""
        canonical = match_name(name, self.object_names)
        try:
            obj = catalog.object_named(canonical)
        except KeyError:
            return None
        if obj.kind not in catalog.SLIDING_KINDS:
            return None
        drawer = obj.parent if obj.kind == "handle" and obj.parent is not None else obj.name
        return drawer_front_normal(self.detect, drawer)


def _in_catalog(name: str) -> bool:
    """Whether the tabletop catalog holds ``name`` (an articulated scene's parts it does not)."""
    try:
        catalog.object_named(name)
    except KeyError:
        return False
    return True
