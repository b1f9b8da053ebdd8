"""Test helper: camera rigs given the sensor model's calibration error, and how far apart their
cameras place the same points."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from voxposer.perception import Observation, SensorNoiseConfig
from voxposer.perception.point_cloud import backproject
from voxposer.perception.sensor_noise import draw_calibration

#: what the sensor model draws per camera: 0.5° about a random axis and 5 mm
CALIBRATION = SensorNoiseConfig()


def miscalibrated(obs: Observation, seed: int) -> Observation:
    """``obs`` with each camera's extrinsics off by a calibration error drawn with ``seed``."""
    offsets = draw_calibration(CALIBRATION, [f.name for f in obs.cameras],
                               np.random.default_rng(seed))
    return replace(obs, cameras=tuple(replace(f, extrinsics=f.extrinsics @ offsets[f.name])
                                      for f in obs.cameras))


def disagreement_mm(exact: Observation, seen: Observation,
                     corrections: dict[str, np.ndarray] | None = None) -> float:
    """Largest median distance [mm] between two cameras' placements of the same points (the
    first camera's workspace pixels), under the views' extrinsics (and ``corrections``)."""
    first = exact.cameras[0]
    pts = backproject(first.depth, first.intrinsics, first.extrinsics).reshape(-1, 3)
    pts = pts[np.all(np.isfinite(pts), axis=1) & (np.abs(pts[:, 0] + 0.2) < 0.5)
              & (np.abs(pts[:, 1]) < 0.5)]
    placed = []
    for truth, frame in zip(exact.cameras, seen.cameras, strict=True):
        err = frame.extrinsics @ np.linalg.inv(truth.extrinsics)
        if corrections is not None:
            err = corrections[frame.name] @ err
        placed.append(pts @ err[:3, :3].T + err[:3, 3])
    return 1000 * max(float(np.median(np.linalg.norm(a - b, axis=1)))
                      for i, a in enumerate(placed) for b in placed[i + 1:])
