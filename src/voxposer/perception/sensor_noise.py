"""Sensor realism for simulated RGB-D views: depth noise, missing depth, calibration error and
corrupted masks, applied to an :class:`~voxposer.perception.observation.Observation`.

The simulator renders perfect views; a consumer RGB-D camera (an Intel RealSense D435 at
0.5–1.5 m) does not. :class:`SensorNoiseConfig` describes what goes wrong, each effect with a
switch and defaults stated as *typical* of such a camera, and :func:`add_sensor_noise` applies it
to an observation, returning a new one (the input is never modified; arrays an effect leaves
alone are shared, not copied). All randomness comes from the :class:`numpy.random.Generator`
passed in: the same generator state gives the same noisy observation.

Missing depth is NaN, which :func:`voxposer.perception.point_cloud.fuse_views` drops like the
background (``inf``). Calibration error is modelled as the perceiver reading perturbed
extrinsics: the pixels stay those of the nominal camera, which is equivalent to pixels from a
perturbed camera read with the nominal extrinsics.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields, replace

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage
from scipy.spatial.transform import Rotation

from voxposer.errors import ConfigError
from voxposer.perception.observation import CameraFrame, Observation

#: The effects' switches, in the order they are applied.
EFFECTS = ("depth_noise", "edge_dropout", "dark_dropout", "calibration", "mask_corruption")


@dataclass(frozen=True)
class SensorNoiseConfig:
    """What a consumer RGB-D camera gets wrong; every effect has a switch (all on by default).

    Attributes:
        depth_noise: add Gaussian depth noise of std σ(z) = a + b·z² [m] at depth z [m].
        depth_noise_base_m: a [m], 0.0005. Typical: the floor of a stereo camera's error
            (quantisation, texture), about 0.5 mm close up.
        depth_noise_quadratic_per_m: b [1/m], 0.0025, so σ(1 m) ≈ 3 mm. Typical of a D435:
            Intel's D400 tuning white paper gives RMS error = z²·subpixel / (f·baseline), with
            subpixel ≈ 0.08, f ≈ 640 px (1280x720) and a 50 mm baseline (≈ 0.0025 z²), within
            the datasheet's "≤ 2 % at 2 m".
        edge_dropout: lose depth at depth edges (stereo occlusion bands at discontinuities).
        edge_jump_m: a pixel is on an edge when its depth differs from a 4-neighbour's by more
            than this [m], 0.03 (typical: a few cm, the size of a block's silhouette step).
        edge_band_px: width of the band around an edge that may lose depth [pixels], 1
            (typical: a few pixels at 1280x720, about one at the simulator's 320x240).
        edge_dropout_p: probability an edge pixel loses its depth, 0.5 (typical: edge bands
            are ragged, about half their pixels invalid).
        dark_dropout: lose depth on dark surfaces (little reflected projector/ambient light).
        dark_intensity: a pixel is dark when its mean RGB intensity is below this (0–1 of
            full scale), 0.1 (typical: near-black, low-albedo surfaces).
        dark_dropout_p: probability a dark pixel loses its depth, 0.5 (typical: active
            stereo recovers some of a dark surface thanks to its IR projector).
        calibration: perturb each camera's extrinsics once per episode (the pose the
            perceiver believes differs from the true one).
        calibration_rotation_deg: rotation of the perturbation about a uniformly random
            axis through the camera centre [deg], 0.5 (typical residual of a checkerboard
            extrinsic / hand-eye calibration: a few tenths of a degree).
        calibration_translation_m: translation of the perturbation in a uniformly random
            direction [m], 0.005 (typical of such calibrations: a few mm).
        mask_corruption: corrupt the segmentation channel (``object_ids``), as an
            open-vocabulary segmenter would; only label-based perception reads it.
        mask_boundary_px: move every mask's boundary by this many pixels: negative erodes
            (the mask loses the object's rim), positive dilates (it bleeds onto the unlabelled
            surroundings); -1 (typical of open-vocabulary masks: boundary errors of a few
            pixels at 1280x720, about one at the simulator's 320x240).
        mask_miss_p: probability an object visible in a view is missed there altogether
            (its pixels unlabelled), 0.05 (typical recall of an open-vocabulary detector on
            tabletop objects: about 0.95).
    """

    depth_noise: bool = True
    depth_noise_base_m: float = 0.0005
    depth_noise_quadratic_per_m: float = 0.0025
    edge_dropout: bool = True
    edge_jump_m: float = 0.03
    edge_band_px: int = 1
    edge_dropout_p: float = 0.5
    dark_dropout: bool = True
    dark_intensity: float = 0.1
    dark_dropout_p: float = 0.5
    calibration: bool = True
    calibration_rotation_deg: float = 0.5
    calibration_translation_m: float = 0.005
    mask_corruption: bool = True
    mask_boundary_px: int = -1
    mask_miss_p: float = 0.05

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            where = f"SensorNoiseConfig.{f.name}"
            if f.name in EFFECTS:
                if not isinstance(value, bool):
                    raise ConfigError(f"{where} must be True or False; got {value!r}")
            elif f.name.endswith("_px"):
                if not (isinstance(value, int) and not isinstance(value, bool)
                        and -64 <= value <= 64):
                    raise ConfigError(f"{where} must be an int in [-64, 64] [pixels]; got "
                                      f"{value!r}")
            elif not (isinstance(value, int | float) and not isinstance(value, bool)
                      and math.isfinite(value) and value >= 0):
                raise ConfigError(f"{where} must be a finite number >= 0; got {value!r}")
        for name in ("edge_dropout_p", "dark_dropout_p", "mask_miss_p", "dark_intensity"):
            if getattr(self, name) > 1:
                raise ConfigError(f"SensorNoiseConfig.{name} must be in [0, 1]; got "
                                  f"{getattr(self, name)!r}")
        if self.edge_band_px < 1:
            raise ConfigError(f"SensorNoiseConfig.edge_band_px must be >= 1 [pixels]; got "
                              f"{self.edge_band_px!r}")
        if self.calibration_rotation_deg > 10:
            raise ConfigError(f"SensorNoiseConfig.calibration_rotation_deg must be in [0, 10] "
                              f"[deg]; got {self.calibration_rotation_deg!r}")

    @classmethod
    def disabled(cls) -> SensorNoiseConfig:
        """Every effect switched off (views pass through unchanged)."""
        return cls(**dict.fromkeys(EFFECTS, False))

    def only(self, *effects: str) -> SensorNoiseConfig:
        """This config with only ``effects`` (names of :data:`EFFECTS`) switched on."""
        unknown = [e for e in effects if e not in EFFECTS]
        if unknown:
            raise ConfigError(f"unknown sensor effect(s) {unknown}; effects are: "
                              f"{', '.join(EFFECTS)}")
        return replace(self, **{e: e in effects for e in EFFECTS})

    @property
    def any_enabled(self) -> bool:
        """Whether some effect is switched on."""
        return any(getattr(self, e) for e in EFFECTS)


def draw_calibration(config: SensorNoiseConfig, cameras: Sequence[str],
                     rng: np.random.Generator) -> dict[str, NDArray[np.float64]]:
    """One calibration error per camera: camera name → 4x4 camera-frame perturbation D, so the
    extrinsics the perceiver reads are ``E @ D`` (rotation of ``calibration_rotation_deg``
    about a random axis through the camera centre, then a shift of
    ``calibration_translation_m`` in a random direction; identity when switched off)."""
    out: dict[str, NDArray[np.float64]] = {}
    for name in cameras:
        offset = np.eye(4)
        if config.calibration:
            axis, shift = rng.standard_normal(3), rng.standard_normal(3)
            axis /= max(float(np.linalg.norm(axis)), 1e-12)
            shift /= max(float(np.linalg.norm(shift)), 1e-12)
            angle = math.radians(config.calibration_rotation_deg)
            offset[:3, :3] = Rotation.from_rotvec(axis * angle).as_matrix()
            offset[:3, 3] = shift * config.calibration_translation_m
        out[name] = offset
    return out


def depth_edges(depth: NDArray[np.float32], jump_m: float, band_px: int = 1
                ) -> NDArray[np.bool_]:
    """Pixels with depth within ``band_px`` pixels of a depth jump larger than ``jump_m`` [m]
    (to a 4-neighbour, background ``inf`` included), shape (H, W), of a depth image [m]."""
    z = depth.astype(np.float64)
    with np.errstate(invalid="ignore"):  # inf − inf: both background, no edge
        jx = np.abs(np.diff(z, axis=1)) > jump_m
        jy = np.abs(np.diff(z, axis=0)) > jump_m
    edge = np.zeros(depth.shape, dtype=bool)
    edge[:, :-1] |= jx
    edge[:, 1:] |= jx
    edge[:-1, :] |= jy
    edge[1:, :] |= jy
    if band_px > 1:
        edge = ndimage.maximum_filter(edge, size=2 * band_px - 1)
    return edge & np.isfinite(depth)


def dark_pixels(rgb: NDArray[np.uint8], intensity: float) -> NDArray[np.bool_]:
    """Pixels whose mean RGB intensity (0–1 of full scale) is below ``intensity``, shape
    (H, W), of an image of shape (H, W, 3)."""
    return np.asarray(rgb.astype(np.float32).mean(axis=-1) < intensity * 255.0)


def corrupt_mask(ids: NDArray[np.int32], boundary_px: int, miss_p: float,
                 rng: np.random.Generator) -> NDArray[np.int32]:
    """A corrupted copy of a label image, shape (H, W) (-1: no object): each object present
    is dropped with probability ``miss_p``, then every mask is eroded (``boundary_px`` < 0)
    or dilated (> 0) by ``|boundary_px|`` pixels (chessboard distance)."""
    out = ids.copy()
    if miss_p > 0:
        present = np.unique(out[out >= 0])
        missed = present[rng.random(len(present)) < miss_p]
        out[np.isin(out, missed)] = -1
    k = abs(boundary_px)
    if boundary_px < 0:  # keep a label only where its whole (2k+1)² window holds it
        lo = ndimage.minimum_filter(out, size=2 * k + 1, mode="nearest")
        hi = ndimage.maximum_filter(out, size=2 * k + 1, mode="nearest")
        out = np.where(lo == hi, out, np.int32(-1)).astype(np.int32)
    elif boundary_px > 0 and np.any(out >= 0):  # unlabelled pixels near a mask join it
        dist, (rows, cols) = ndimage.distance_transform_cdt(
            out < 0, metric="chessboard", return_indices=True)
        grow = (out < 0) & (dist <= k)
        out[grow] = out[rows[grow], cols[grow]]
    return out


def _noisy_frame(frame: CameraFrame, config: SensorNoiseConfig, rng: np.random.Generator,
                 offset: NDArray[np.float64] | None) -> CameraFrame:
    """``frame`` with ``config``'s per-view effects and the calibration ``offset`` applied."""
    depth, finite = frame.depth, np.isfinite(frame.depth)
    drop = np.zeros(depth.shape, dtype=bool)
    if config.edge_dropout:  # edges of the true depth, before the noise
        drop |= depth_edges(depth, config.edge_jump_m, config.edge_band_px) & (
            rng.random(depth.shape) < config.edge_dropout_p)
    if config.dark_dropout and frame.rgb.any():  # an all-black image had no colour rendered
        drop |= dark_pixels(frame.rgb, config.dark_intensity) & finite & (
            rng.random(depth.shape) < config.dark_dropout_p)
    if config.depth_noise:
        z = np.where(finite, depth, np.float32(0.0)).astype(np.float32)
        sigma = config.depth_noise_base_m + config.depth_noise_quadratic_per_m * z * z
        noisy = z + sigma.astype(np.float32) * rng.standard_normal(depth.shape, np.float32)
        depth = np.where(finite, np.maximum(noisy, np.float32(1e-4)), depth).astype(np.float32)
    if drop.any():
        depth = np.where(drop, np.float32(np.nan), depth).astype(np.float32)
    ids = frame.object_ids
    if config.mask_corruption:
        ids = corrupt_mask(ids, config.mask_boundary_px, config.mask_miss_p, rng)
    extrinsics = frame.extrinsics if offset is None else frame.extrinsics @ offset
    return replace(frame, depth=depth, object_ids=ids, extrinsics=extrinsics)


def add_sensor_noise(obs: Observation, config: SensorNoiseConfig, rng: np.random.Generator,
                     calibration: Mapping[str, NDArray[np.float64]] | None = None
                     ) -> Observation:
    """A noisy copy of ``obs``: every view with ``config``'s effects (the input is unchanged).

    Args:
        obs: the observation (depth [m], rgb, extrinsics, label channel of each view).
        config: the effects and their sizes.
        rng: all randomness of the call (same state → same result).
        calibration: camera name → 4x4 perturbation (:func:`draw_calibration`), for a
            calibration error kept over an episode; None: drawn from ``rng`` now (first,
            in camera order) when ``config.calibration`` is on.

    Raises:
        KeyError: ``calibration`` lacks one of the views' cameras (lists those it has).
    """
    if not config.any_enabled:
        return replace(obs)
    names = [f.name for f in obs.cameras]
    if calibration is None and config.calibration:
        calibration = draw_calibration(config, names, rng)
    if calibration is not None and config.calibration:
        missing = [n for n in names if n not in calibration]
        if missing:
            raise KeyError(f"no calibration error for camera(s) {missing}; it has: "
                           f"{sorted(calibration)}")
    frames = tuple(_noisy_frame(f, config, rng, calibration[f.name]
                                if calibration is not None and config.calibration else None)
                   for f in obs.cameras)
    return replace(obs, cameras=frames)


__all__ = ["EFFECTS", "SensorNoiseConfig", "add_sensor_noise", "corrupt_mask", "dark_pixels",
           "depth_edges", "draw_calibration"]
