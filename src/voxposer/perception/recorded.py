"""Observations saved to disk and served again: perception without the simulator.

``save_observation`` writes one :class:`Observation` (every camera's RGB, depth, intrinsics,
extrinsics and segmentation channel, plus the robot state and label names) to a compressed
``.npz``; ``load_observation`` reads it back. :class:`RecordedObservations` is an
:class:`~voxposer.perception.perceiver.ObservationSource` that serves a loaded observation, so a
perceiver runs on data captured elsewhere (another machine, a real camera rig, a bug report).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from voxposer.errors import ConfigError
from voxposer.perception.observation import CameraFrame, Observation

_FIELDS = ("rgb", "depth", "intrinsics", "extrinsics", "object_ids")


def save_observation(obs: Observation, path: str | Path) -> Path:
    """Write ``obs`` to ``path`` (``.npz``, compressed); returns the path written."""
    out = Path(path)
    arrays = {f"{k}_{field}": getattr(frame, field)
              for k, frame in enumerate(obs.cameras) for field in _FIELDS}
    meta = {"time": obs.time, "gripper": obs.gripper, "label_names": list(obs.label_names),
            "cameras": [f.name for f in obs.cameras]}
    np.savez_compressed(out, ee_position=obs.ee_position, ee_quat=obs.ee_quat,
                        meta=np.array(json.dumps(meta)), **arrays)
    return out if out.suffix == ".npz" else out.with_name(out.name + ".npz")


def load_observation(path: str | Path) -> Observation:
    """The observation saved at ``path`` by :func:`save_observation`.

    Raises:
        ConfigError: the file is missing or is not a saved observation.
    """
    p = Path(path)
    if not p.is_file():
        raise ConfigError(f"no saved observation at {p}")
    with np.load(p, allow_pickle=False) as data:
        if "meta" not in data:
            raise ConfigError(f"{p} is not a saved observation (no 'meta' entry)")
        meta = json.loads(str(data["meta"]))
        frames = tuple(
            CameraFrame(name, *(np.array(data[f"{k}_{field}"]) for field in _FIELDS))
            for k, name in enumerate(meta["cameras"]))
        return Observation(time=float(meta["time"]), cameras=frames,
                           ee_position=np.array(data["ee_position"]),
                           ee_quat=np.array(data["ee_quat"]), gripper=float(meta["gripper"]),
                           label_names=tuple(meta["label_names"]))


class RecordedObservations:
    """An observation source serving one saved observation (a static scene).

    Args:
        observation: what every ``observe`` returns.
        object_names: the objects in the scene (default: every label that some pixel shows).
    """

    def __init__(self, observation: Observation, object_names: tuple[str, ...] | None = None
                 ) -> None:
        self.observation = observation
        if object_names is None:
            seen = set(np.unique(np.concatenate([f.object_ids.ravel()
                                                 for f in observation.cameras])).tolist())
            object_names = tuple(n for k, n in enumerate(observation.label_names) if k in seen)
        self._names = tuple(object_names)

    @property
    def object_names(self) -> tuple[str, ...]:
        return self._names

    def observe(self, *, rgb: bool = True, labels: bool = True) -> Observation:
        return self.observation
