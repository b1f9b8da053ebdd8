"""Cameras registered against each other once per episode, before anything is fused.

:class:`RegisteredObservationSource` wraps an
:class:`~voxposer.perception.perceiver.ObservationSource` (a rig whose extrinsics carry
calibration error: the simulator through
:class:`~voxposer.perception.noisy_source.NoisyObservationSource`, or real cameras) and serves its
observations with each camera's extrinsics corrected by
:func:`~voxposer.perception.surface_registration.register_clouds`. The correction is measured on
the first observation of an episode — the robot still, every camera's frame from one instant —
and kept until the observed time goes back (the scene was reset), as a rig is checked once per
session rather than every frame.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.observation import CameraFrame, Observation
from voxposer.perception.perceiver import ObservationSource
from voxposer.perception.point_cloud import backproject
from voxposer.perception.surface_registration import RegistrationConfig, register_clouds


def register_views(frames: Sequence[CameraFrame], grid: VoxelGrid,
                   config: RegistrationConfig | None = None) -> dict[str, NDArray[np.float64]]:
    """Camera name → 4x4 world-frame correction of its extrinsics (``C @ E``) making ``frames``
    agree on the workspace ``grid``'s box (see
    :func:`~voxposer.perception.surface_registration.register_clouds`)."""
    clouds = []
    for frame in frames:
        points = backproject(frame.depth, frame.intrinsics, frame.extrinsics).reshape(-1, 3)
        clouds.append(points[grid.contains(points)])  # NaN points (no depth) are outside
    moves = register_clouds(clouds, config)
    return {frame.name: move for frame, move in zip(frames, moves, strict=True)}


class RegisteredObservationSource:
    """An :class:`~voxposer.perception.perceiver.ObservationSource` serving ``source``'s
    observations with the cameras registered against each other.

    Args:
        source: what observes the scene.
        grid: the workspace; only points inside its box are registered.
        config: see :class:`~voxposer.perception.surface_registration.RegistrationConfig`.
    """

    def __init__(self, source: ObservationSource, grid: VoxelGrid,
                 config: RegistrationConfig | None = None) -> None:
        self.source = source
        self.grid = grid
        self.config = config or RegistrationConfig()
        #: camera name → correction of the current episode (empty before the first observation)
        self.corrections: dict[str, NDArray[np.float64]] = {}
        self._last_time: float | None = None
        self._raw: Observation | None = None
        self._served: Observation | None = None
        self._frames: dict[str, tuple[CameraFrame, CameraFrame]] = {}

    @property
    def object_names(self) -> tuple[str, ...]:
        return tuple(self.source.object_names)

    def observe(self, *, rgb: bool = True, labels: bool = True) -> Observation:
        """``source``'s current observation, its extrinsics corrected; the same object while
        ``source`` serves the same one, and a camera's frame the same object while ``source``'s
        is (fusion reuses the points of a camera whose next frame is not due)."""
        raw = self.source.observe(rgb=rgb, labels=labels)
        if raw is self._raw and self._served is not None:
            return self._served
        if self._last_time is None or raw.time < self._last_time \
                or any(f.name not in self.corrections for f in raw.cameras):
            self.corrections = register_views(raw.cameras, self.grid, self.config)
            self._frames = {}
        self._last_time = raw.time
        self._raw = raw
        self._served = replace(raw, cameras=tuple(self._corrected(f) for f in raw.cameras))
        return self._served

    def _corrected(self, frame: CameraFrame) -> CameraFrame:
        held = self._frames.get(frame.name)
        if held is not None and held[0] is frame:
            return held[1]
        out = replace(frame, extrinsics=self.corrections[frame.name] @ frame.extrinsics)
        self._frames[frame.name] = (frame, out)
        return out


__all__ = ["RegisteredObservationSource", "register_views"]
