"""Open-vocabulary perception (the paper's real-world pipeline, App. A.5): detector boxes for the
queried names, box-prompted masks, masks tracked between frames, lifted to 3-D with RGB-D and
calibration.

:class:`OpenVocabPerceiver` is a :class:`~voxposer.perception.perceiver.Perceiver` reading only
each view's RGB, depth, intrinsics and extrinsics (never the segmentation channel). The detector
runs on the first observation after the queries are set (:meth:`OpenVocabPerceiver.set_queries`,
once per sub-task) and again whenever tracking loses an object; in between, the
:class:`~voxposer.perception.open_vocab.tracker.MaskTracker` carries the masks. Objects are named
after their query ("drawer handle"); several instances of one are "block", "block 2"… and keep
their names while tracked or re-detected nearby. Unlabelled points (the robot, the table, unless
queried) are obstacles; querying "robot" and "gripper" leaves the robot out of them.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Sequence
from typing import Final

import numpy as np
from numpy.typing import NDArray

from voxposer import catalog
from voxposer.errors import ConfigError, ObjectNotVisibleError, UnknownObjectError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.detect import DetectedObject, detect_in_cloud
from voxposer.perception.names import match_name, normalize_name
from voxposer.perception.observation import Observation
from voxposer.perception.occlusion_memory import REMEMBERED_KINDS, OcclusionMemory
from voxposer.perception.open_vocab.detector import Detector
from voxposer.perception.open_vocab.fusion import (
    Instance,
    ViewMask,
    fuse_masks,
    labelled_cloud,
    world_points,
)
from voxposer.perception.open_vocab.segmenter import Segmenter
from voxposer.perception.open_vocab.tracker import MaskTracker
from voxposer.perception.perceiver import ObservationSource
from voxposer.perception.point_cloud import PointCloud
from voxposer.perception.scene_occupancy import scene_occupancy
from voxposer.perception.sliding_axis import dominant_normal, drawer_front_normal

log = logging.getLogger(__name__)

#: The queries when none are given: every name of the tabletop catalog.
DEFAULT_QUERIES: Final = tuple(o.name for o in catalog.OBJECTS)
#: The stages whose times [ms] are recorded in ``OpenVocabPerceiver.stage_times_ms``.
STAGES: Final = ("detector", "segmenter", "tracker", "fusion")


def _checked(queries: Sequence[str]) -> tuple[str, ...]:
    """``queries`` as a tuple of distinct non-empty names; raises ConfigError otherwise."""
    if isinstance(queries, str):
        raise ConfigError(f"queries must be a sequence of names, not one string: {queries!r}")
    out = tuple(str(q).strip() for q in queries)
    if not out or any(not q for q in out):
        raise ConfigError(f"queries must be one or more non-empty names; got {list(queries)!r}")
    keys = [normalize_name(q) for q in out]
    if len(set(keys)) < len(keys):
        raise ConfigError(f"queries name one object twice: {list(out)!r}")
    return out


class OpenVocabPerceiver:
    """A :class:`~voxposer.perception.perceiver.Perceiver` detecting queried names with an
    open-vocabulary detector and a box-prompted segmenter, tracking them between frames.

    Args:
        source: what observes the scene; asked for colour.
        grid: the workspace grid; the fused cloud is cropped to it.
        detector: boxes for text queries (e.g. :class:`OwlDetector`).
        segmenter: masks for boxes (e.g. :class:`SamSegmenter`).
        queries: the names to look for (objects or parts: "drawer handle").
        tracker: carries masks between detections (default: a :class:`MaskTracker` on
            ``segmenter``).
    """

    def __init__(self, source: ObservationSource, grid: VoxelGrid, detector: Detector,
                 segmenter: Segmenter, *, queries: Sequence[str] = DEFAULT_QUERIES,
                 tracker: MaskTracker | None = None) -> None:
        self.source = source
        self._grid = grid
        self.detector = detector
        self.segmenter = segmenter
        self.tracker = tracker if tracker is not None else MaskTracker(segmenter)
        self._queries = _checked(queries)
        self._obs: Observation | None = None
        self._instances: tuple[Instance, ...] = ()
        self._cloud: PointCloud | None = None
        self._redetect = True
        #: the parts of blocks and lines other objects hide now (a block on a line's end)
        self._memory = OcclusionMemory()
        self._detections: dict[str, DetectedObject] = {}
        #: how many times the detector ran (over every camera of one observation)
        self.detector_runs = 0
        #: per stage (:data:`STAGES`), the time [ms] of each run
        self.stage_times_ms: dict[str, list[float]] = {s: [] for s in STAGES}

    @property
    def grid(self) -> VoxelGrid:
        return self._grid

    @property
    def queries(self) -> tuple[str, ...]:
        """The names the detector is asked for."""
        return self._queries

    def set_queries(self, queries: Sequence[str]) -> None:
        """Look for ``queries`` from now on (a new sub-task): the detector runs on the next
        observation and objects are named afresh."""
        self._queries = _checked(queries)
        self.reset()

    def reset(self) -> None:
        """Forget the tracked objects; the detector runs on the next observation."""
        self._instances, self._cloud, self._redetect = (), None, True
        self._memory.forget()
        self._detections = {}

    @property
    def instances(self) -> tuple[Instance, ...]:
        """The objects of the latest observation, most confident first."""
        self._update()
        return self._instances

    @property
    def object_names(self) -> tuple[str, ...]:
        """Names of the objects detected (or tracked) in the latest observation."""
        return tuple(inst.name for inst in self.instances)

    def observe(self) -> Observation:
        obs = self.source.observe(rgb=True, labels=False)  # pixels only: no label ids
        if obs is not self._obs:
            self._obs, self._cloud, self._detections = obs, None, {}
        return obs

    def _timed(self, stage: str, start: float) -> None:
        self.stage_times_ms[stage].append((time.perf_counter() - start) * 1e3)

    def _detect(self, obs: Observation, points: list[NDArray[np.float64]],
                previous: Sequence[Instance]) -> tuple[Instance, ...]:
        """Detect, segment and fuse every camera's view of ``obs``."""
        masks: list[ViewMask] = []
        for cam, frame in enumerate(obs.cameras):
            start = time.perf_counter()
            found = self.detector.detect(frame.rgb, self._queries)
            self._timed("detector", start)
            start = time.perf_counter()
            segments = self.segmenter.segment(frame.rgb, np.array([d.box for d in found]))
            self._timed("segmenter", start)
            masks += [ViewMask(cam, d.query, m, d.score)
                      for d, m in zip(found, segments, strict=True)]
        self.detector_runs += 1
        start = time.perf_counter()
        out = fuse_masks(obs.cameras, masks, self._grid, self._queries, previous, points)
        self._timed("fusion", start)
        log.debug("open-vocabulary detection found: %s", ", ".join(i.name for i in out))
        return out

    def _update(self) -> PointCloud:
        """Bring the objects and the labelled cloud up to the latest observation; the cloud."""
        obs = self.observe()
        if self._cloud is not None:
            return self._cloud
        points = world_points(obs.cameras)
        if self._redetect or not self._instances:
            self._instances = self._detect(obs, points, ())
        else:
            start = time.perf_counter()
            step = self.tracker.step(obs.cameras, self._instances, self._grid, points)
            self._timed("tracker", start)
            if step.lost:
                log.debug("tracking lost %s; detecting again", ", ".join(step.lost))
                tracked = {i.name for i in step.instances}
                previous = step.instances + tuple(i for i in self._instances
                                                  if i.name not in tracked)
                self._instances = self._detect(obs, points, previous)
            else:
                self._instances = step.instances
        self._redetect = False
        start = time.perf_counter()
        self._cloud = labelled_cloud(obs.cameras, self._instances, self._grid)
        self._timed("fusion", start)
        return self._cloud

    def point_cloud(self) -> PointCloud:
        """The fused cloud; labels index :attr:`instances` (-1: no detected object)."""
        return self._update()

    def _canonical(self, name: str) -> str:
        names = self.object_names
        try:
            return match_name(name, names)
        except UnknownObjectError:
            raise ObjectNotVisibleError(
                f"the open-vocabulary detector found no {name!r} (queries: "
                f"{', '.join(self._queries)}); it detected: {', '.join(names) or 'nothing'}"
            ) from None

    def detect(self, name: str) -> DetectedObject:
        """Object ``name`` ("block 2", "the drawer handle") among the detected ones; a catalog
        object also gathers its detected parts ("top drawer" with its handle).

        Raises:
            ObjectNotVisibleError: no detected object has that name (names the query and what
                was detected).
        """
        canonical = self._canonical(name)
        cloud = self.point_cloud()
        names = self.object_names
        members = set(catalog.family(canonical)) if canonical in DEFAULT_QUERIES else set()
        members.add(canonical)
        labels = np.asarray([k for k, n in enumerate(names) if n in members], dtype=np.int32)
        if canonical in self._detections:  # once per fused cloud (the memory moves on)
            return self._detections[canonical]
        kind = _kind(canonical)
        found = detect_in_cloud(cloud, labels, canonical, self._grid,
                                horizontal_normal=kind in catalog.SLIDING_KINDS)
        if kind in REMEMBERED_KINDS:
            obs = self.observe()
            found = self._memory.extend(found, obs.cameras, self._grid, obs.time)
        self._detections[canonical] = found
        return found

    def scene_occupancy(self, entity: str, *, holding: bool, ignore_table: bool = False
                        ) -> NDArray[np.bool_]:
        obs = self.observe()
        return scene_occupancy(self.point_cloud(), self.object_names, obs.ee_position,
                               self._grid, entity=entity, holding=holding,
                               ignore_table=ignore_table)

    def sliding_axis(self, name: str) -> NDArray[np.float64] | None:
        """For a catalog drawer or handle, the outward normal of the drawer's front (the
        handle's own when its drawer was not detected); None for anything else."""
        canonical = self._canonical(name)
        if _kind(canonical) not in catalog.SLIDING_KINDS:
            return None
        obj = catalog.object_named(canonical)
        drawer = obj.parent if obj.kind == "handle" and obj.parent in self.object_names else None
        if drawer is not None:
            return drawer_front_normal(self.detect, drawer)
        return dominant_normal(np.asarray(self.detect(canonical).normals, dtype=np.float64))


def _kind(name: str) -> str | None:
    """The catalog kind of ``name``, None for a name the catalog does not hold."""
    try:
        return catalog.object_named(name).kind
    except UnknownObjectError:
        return None
