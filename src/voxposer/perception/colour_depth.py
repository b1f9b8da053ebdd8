"""Perception from RGB-D pixels alone: colour words, depth clusters and a cabinet fit.

:class:`ColourDepthPerceiver` is a :class:`~voxposer.perception.perceiver.Perceiver` that reads
only each view's RGB, depth, intrinsics and extrinsics and the robot's own end-effector pose
(never the segmentation channel, the simulator's state or its list of objects). It finds the
catalog's coloured blocks and lines by colour and 3-D shape, the cabinet (a known fixture) with
its drawers' openings measured from depth, the table and the robot
(:mod:`voxposer.perception.pixel_labels`); everything downstream (``detect``, obstacles,
sliding directions) works on its labelled cloud as on the ground-truth one.

The objects it knows are those it has seen: every object found in some observation since it was
made stays nameable (an object the gripper hides for a while is still there); ``detect`` of a block
or line no camera sees now gives it where it was last seen when other objects cover that place
(the occlusion memory's recall), and otherwise raises
:class:`~voxposer.errors.ObjectNotVisibleError`; a name never seen raises
:class:`~voxposer.errors.UnknownObjectError`.
"""

from __future__ import annotations

import logging
import time

import numpy as np
from numpy.typing import NDArray

from voxposer import catalog
from voxposer.errors import ObjectNotVisibleError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.detect import DetectedObject, detect_in_cloud
from voxposer.perception.label_tracking import LabelTrackingConfig, track_labels
from voxposer.perception.names import match_name
from voxposer.perception.observation import Observation
from voxposer.perception.occlusion_memory import REMEMBERED_KINDS, OcclusionMemory
from voxposer.perception.perceiver import ObservationSource
from voxposer.perception.pixel_labels import PixelLabels, ViewClouds, label_pixels
from voxposer.perception.point_cloud import PointCloud
from voxposer.perception.scene_occupancy import scene_occupancy
from voxposer.perception.sliding_axis import drawer_front_normal

log = logging.getLogger(__name__)

#: The names a scene always has: the table and the robot observing it.
_FIXED = ("table", "robot", "gripper")
_LABEL_NAMES = tuple(o.name for o in catalog.OBJECTS)


class ColourDepthPerceiver:
    """A :class:`~voxposer.perception.perceiver.Perceiver` detecting objects from RGB and depth
    pixels (colour segmentation, depth clustering, a cabinet fit); weight-free.

    Args:
        source: what observes the scene; asked for colour and no label ids
            (``observe(rgb=True, labels=False)``).
        grid: the workspace grid; the fused cloud is cropped to it.
        tracking: between full detections, carry the labels of the last cloud to the new one
            (:mod:`voxposer.perception.label_tracking`: a detection at least every
            ``redetect_s`` of observation time, and whenever tracking gives up); None: detect
            in every observation.
    """

    def __init__(self, source: ObservationSource, grid: VoxelGrid,
                 tracking: LabelTrackingConfig | None = None) -> None:
        self.source = source
        self._grid = grid
        self.tracking = tracking
        #: the last full detection: its observation time [s] and unexplained chromatic points
        self._detected: tuple[float, int] | None = None
        #: per new observation: whether its labels were carried (True) or detected (False)
        self.carried: list[bool] = []
        self._obs: Observation | None = None
        self._labels: PixelLabels | None = None
        self._last: PixelLabels | None = None
        self._known: dict[str, None] = dict.fromkeys(_FIXED)
        self._openings: dict[str, float] = {}
        self._tracks: dict[str, NDArray[np.float64]] = {}
        #: each camera's last frame and its coloured points (a frame not renewed is kept)
        self._views: ViewClouds = {}
        #: the parts of blocks and lines other objects hide now (a block on a line's end)
        self._memory = OcclusionMemory()
        self._detections: dict[str, DetectedObject] = {}
        #: time [ms] each labelling took (one per new observation)
        self.label_times_ms: list[float] = []

    @property
    def grid(self) -> VoxelGrid:
        return self._grid

    @property
    def object_names(self) -> tuple[str, ...]:
        """Every object seen since this perceiver was made (table, robot, gripper always), in
        catalog order."""
        self._labelled()
        return tuple(n for n in _LABEL_NAMES if n in self._known)

    def observe(self) -> Observation:
        obs = self.source.observe(rgb=True, labels=False)  # pixels only: no label ids
        if obs is not self._obs:
            self._obs, self._labels, self._detections = obs, None, {}
        return obs

    def _labelled(self) -> PixelLabels:
        obs = self.observe()
        if self._labels is None:
            start = time.perf_counter()
            self._labels = self._carried(obs)
            self.carried.append(self._labels is not None)
            if self._labels is None:
                self._labels = label_pixels(obs, self._grid, self._openings, self._tracks,
                                            self._views)
                self._detected = (float(obs.time), self._labels.unexplained)
            self._last = self._labels
            self.label_times_ms.append((time.perf_counter() - start) * 1e3)
            self._openings.update(self._labels.openings)
            self._tracks.update(self._labels.tracks)
            new = [n for n in self._labels.seen if n not in self._known]
            if new:
                log.debug("colour-depth perception found: %s", ", ".join(new))
            self._known.update(dict.fromkeys(self._labels.seen))
            if self._labels.cabinet:
                self._known.update(dict.fromkeys(catalog.family("cabinet")))
        return self._labels

    def _carried(self, obs: Observation) -> PixelLabels | None:
        """The labels of ``obs`` carried from the last cloud, when tracking is on, a detection
        is not due and tracking holds; else None."""
        if self.tracking is None or self._detected is None or self._last is None:
            return None
        if float(obs.time) - self._detected[0] >= self.tracking.redetect_s:
            return None
        return track_labels(obs, self._grid, self._last, self.tracking, self._detected[1],
                            self._views)

    def point_cloud(self) -> PointCloud:
        """The fused cloud, labelled from pixels (labels index :data:`catalog.OBJECTS`)."""
        return self._labelled().cloud

    def drawer_opening(self, drawer: str) -> float:
        """How far ``drawer`` ("top", "top drawer") is open [m], as measured from depth.

        Raises:
            UnknownObjectError: not a drawer this perceiver has seen (lists the known names).
            ObjectNotVisibleError: no camera has seen the drawer's front yet.
        """
        labels = self._labelled()
        canonical = match_name(drawer if "drawer" in drawer else f"{drawer} drawer",
                               self.object_names)
        which = canonical.removesuffix(" drawer handle").removesuffix(" drawer")
        if which not in self._openings:
            raise ObjectNotVisibleError(f"no camera has seen the front of the {which} drawer")
        return labels.openings.get(which, self._openings[which])

    def detect(self, name: str) -> DetectedObject:
        """Find ``name`` ("blue block", "the top drawer's handle"…) among the pixels' objects.

        Raises:
            UnknownObjectError: the name matches no object seen (lists them).
            ObjectNotVisibleError: the object was seen before but no camera sees it now, and
                it is not recalled as hidden where it was
                (:meth:`~voxposer.perception.occlusion_memory.OcclusionMemory.recall`).
        """
        canonical = match_name(name, self.object_names)
        cloud = self.point_cloud()
        if canonical in self._detections:  # once per observation (the memory moves on)
            return self._detections[canonical]
        members = set(catalog.family(canonical))
        labels = np.asarray([k for k, n in enumerate(_LABEL_NAMES) if n in members],
                            dtype=np.int32)
        kind = catalog.object_named(canonical).kind
        try:
            found = detect_in_cloud(cloud, labels, canonical, self._grid,
                                    horizontal_normal=kind in catalog.SLIDING_KINDS)
        except ObjectNotVisibleError:  # wholly hidden: where it was, if something covers it
            obs = self.observe()
            recalled = (self._memory.recall(canonical, obs.cameras, self._grid, obs.time)
                        if kind in REMEMBERED_KINDS else None)
            if recalled is None:
                raise
            found = recalled
        else:
            if kind in REMEMBERED_KINDS:
                obs = self.observe()
                found = self._memory.extend(found, obs.cameras, self._grid, obs.time)
        self._detections[canonical] = found
        return found

    def scene_occupancy(self, entity: str, *, holding: bool, ignore_table: bool = False
                        ) -> NDArray[np.bool_]:
        obs = self.observe()
        return scene_occupancy(self.point_cloud(), _LABEL_NAMES, obs.ee_position, self._grid,
                               entity=entity, holding=holding, ignore_table=ignore_table)

    def sliding_axis(self, name: str) -> NDArray[np.float64] | None:
        """The outward normal of a drawer's front (for a drawer or its handle), as measured;
        None for objects that do not slide."""
        canonical = match_name(name, self.object_names)
        obj = catalog.object_named(canonical)
        if obj.kind not in catalog.SLIDING_KINDS:
            return None
        drawer = obj.parent if obj.kind == "handle" and obj.parent is not None else obj.name
        return drawer_front_normal(self.detect, drawer)


__all__ = ["ColourDepthPerceiver"]
