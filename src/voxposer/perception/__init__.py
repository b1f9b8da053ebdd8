"""Perception: observations, fused labelled point clouds, detection, obstacles, object names.

Public API:

* :class:`Observation`, :class:`CameraFrame` (what a robot's cameras report)
* :class:`PointCloud`, :func:`fuse_views`, :func:`backproject`, :func:`camera_normals`
* :class:`Perceiver` and :class:`ObservationSource` (the seam), :class:`SegmentationPerceiver`
  (detection from a segmentation channel: the simulator's ground truth),
  :class:`ColourDepthPerceiver` (detection from RGB-D pixels only: colour words, depth clusters,
  a cabinet fit)
* :class:`DetectedObject` (a frozen dataclass that also reads like a dict), :func:`detect_in_cloud`
* :func:`scene_occupancy`, :func:`match_name`, :func:`normalize_name`, :func:`is_end_effector`
* :class:`SensorNoiseConfig`, :func:`add_sensor_noise` (a consumer RGB-D camera's errors on
  simulated views) and :class:`NoisyObservationSource` (a source serving noisy views)
* :class:`RegisteredObservationSource` (a source whose cameras are registered against each
  other once per episode, :func:`register_views`) and :class:`RegistrationConfig`
"""

from voxposer.perception.colour_depth import ColourDepthPerceiver
from voxposer.perception.detect import DetectedObject, detect_in_cloud
from voxposer.perception.names import is_end_effector, match_name, normalize_name
from voxposer.perception.noisy_source import NoisyObservationSource
from voxposer.perception.observation import CameraFrame, Observation
from voxposer.perception.perceiver import ObservationSource, Perceiver
from voxposer.perception.point_cloud import (
    PointCloud,
    backproject,
    camera_normals,
    fuse_views,
)
from voxposer.perception.scene_occupancy import scene_occupancy
from voxposer.perception.segmentation import SegmentationPerceiver
from voxposer.perception.sensor_noise import SensorNoiseConfig, add_sensor_noise
from voxposer.perception.surface_registration import RegistrationConfig
from voxposer.perception.view_registration import RegisteredObservationSource, register_views

__all__ = [
    "CameraFrame",
    "ColourDepthPerceiver",
    "DetectedObject",
    "NoisyObservationSource",
    "Observation",
    "ObservationSource",
    "Perceiver",
    "PointCloud",
    "RegisteredObservationSource",
    "RegistrationConfig",
    "SegmentationPerceiver",
    "SensorNoiseConfig",
    "add_sensor_noise",
    "backproject",
    "camera_normals",
    "detect_in_cloud",
    "fuse_views",
    "is_end_effector",
    "match_name",
    "normalize_name",
    "register_views",
    "scene_occupancy",
]
