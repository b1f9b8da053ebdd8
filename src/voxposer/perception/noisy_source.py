"""An observation source whose views carry simulated sensor errors
(:mod:`voxposer.perception.sensor_noise`), for perceivers to read instead of the perfect
simulator.

:class:`NoisyObservationSource` wraps any
:class:`~voxposer.perception.perceiver.ObservationSource` (the MuJoCo world) and applies
:func:`~voxposer.perception.sensor_noise.add_sensor_noise` to what it observes. It is
deterministic: the noise of an observation depends only on the seed, the episode and the
observation's time, so asking twice at one instant (or once with colour and once without) gives
the same views, and the same episode replayed gives the same noise. A camera whose frame is the
very one ``source`` served before (a camera streaming at its own rate whose next frame is not
due: ``CameraConfig.frame_hz``) keeps that frame's noisy copy, as a real camera's frame is one
image until the next; only new frames are noised, drawn in camera order from the seed, the
episode and the time of the observation that brought them. Each camera's calibration
error is drawn once per episode and kept; an episode starts when the source is made and again
whenever the observed time goes back (the world was reset).
"""

from __future__ import annotations

import hashlib
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.perception.observation import CameraFrame, Observation
from voxposer.perception.perceiver import ObservationSource
from voxposer.perception.sensor_noise import SensorNoiseConfig, add_sensor_noise, draw_calibration


def seed_from_scene(scene: object) -> int:
    """A stable seed (an int in [0, 2⁶³)) from a scene description's ``repr`` (e.g. the world's
    ``placement``): the same scene gives the same seed in every process."""
    digest = hashlib.sha256(repr(scene).encode()).digest()
    return int.from_bytes(digest[:8], "little") >> 1


class NoisyObservationSource:
    """An :class:`~voxposer.perception.perceiver.ObservationSource` serving ``source``'s
    observations with sensor errors.

    Args:
        source: what observes the scene (e.g. :class:`voxposer.envs.TabletopWorld`).
        config: the effects and their sizes.
        seed: the noise's seed (an int >= 0); see the module docstring for what it fixes.
    """

    def __init__(self, source: ObservationSource, config: SensorNoiseConfig, seed: int) -> None:
        if not (isinstance(seed, int | np.integer) and seed >= 0):
            raise ConfigError(f"NoisyObservationSource seed must be an int >= 0; got {seed!r}")
        self.source = source
        self.config = config
        self.seed = int(seed)
        #: episodes begun so far (0 until the first reset seen)
        self.episode = 0
        self._calibration: dict[str, NDArray[np.float64]] | None = None
        self._last_time: float | None = None
        self._raw: Observation | None = None
        self._noisy: Observation | None = None
        #: camera name → (the source's frame, its noisy copy) of the frames served last
        self._frames: dict[str, tuple[CameraFrame, CameraFrame]] = {}

    @property
    def object_names(self) -> tuple[str, ...]:
        return tuple(self.source.object_names)

    def observe(self, *, rgb: bool = True, labels: bool = True) -> Observation:
        """``source``'s current observation with noise; the same object while ``source``
        serves the same one. Colour is always observed when dark-surface dropout is on (it
        decides which pixels lose depth)."""
        raw = self.source.observe(rgb=rgb or self.config.dark_dropout, labels=labels)
        if raw is self._raw and self._noisy is not None:
            return self._noisy
        if self._last_time is not None and raw.time < self._last_time:
            self.episode += 1
            self._calibration = None
            self._frames = {}
        self._last_time = raw.time
        if self._calibration is None:
            rng = np.random.default_rng([self.seed, self.episode, 0, 0])
            self._calibration = draw_calibration(self.config, [f.name for f in raw.cameras],
                                                 rng)
        elif any(f.name not in self._calibration for f in raw.cameras):  # a camera was added
            rng = np.random.default_rng([self.seed, self.episode, 0, len(self._calibration)])
            new = [f.name for f in raw.cameras if f.name not in self._calibration]
            self._calibration.update(draw_calibration(self.config, new, rng))
        rng = np.random.default_rng([self.seed, self.episode, 1, round(raw.time * 1e6)])
        held = [self._held(f) for f in raw.cameras]
        fresh = tuple(f for f, h in zip(raw.cameras, held, strict=True) if h is None)
        noised = iter(add_sensor_noise(replace(raw, cameras=fresh), self.config, rng,
                                       self._calibration).cameras if fresh else ())
        frames = tuple(next(noised) if h is None else h for h in held)
        self._frames = {f.name: (f, n) for f, n in zip(raw.cameras, frames, strict=True)}
        self._raw = raw
        self._noisy = replace(raw, cameras=frames)
        return self._noisy

    def _held(self, frame: CameraFrame) -> CameraFrame | None:
        """The noisy copy made of ``frame`` before, if it is the frame served last time."""
        held = self._frames.get(frame.name)
        return held[1] if held is not None and held[0] is frame else None


__all__ = ["NoisyObservationSource", "seed_from_scene"]
