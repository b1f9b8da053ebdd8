"""Recorded RGB-D frames: a folder of images plus one JSON, as a real camera rig would save them.

Format ``voxposer-frames`` version 1 — a folder holding ``frames.json`` and, per camera ``<name>``:

* ``<name>_colour.png``: colour, 8-bit RGB, shape (H, W, 3);
* ``<name>_depth.png``: depth along the optical axis, 16-bit grey, in millimetres (``depth_unit``
  "mm"; 1 mm steps, at most 65.535 m); 0 = no reading (background, a hole), read back as ``inf``;
* ``<name>_labels.png`` (only when saved with labels): 16-bit grey, the segmentation label + 1
  (0 = no object), an index into ``labels`` of ``frames.json``.

``frames.json``: ``format`` ("voxposer-frames"), ``version`` (1), ``time_s``, ``depth_unit``
("mm"), ``robot`` (``ee_position_m`` [m] (3,), ``ee_quat_xyzw`` (4,), ``gripper`` (1 closed, 0
open), ``gripper_opening_m`` [m] or null), ``labels`` (label names, or null: no segmentation, as
from a real camera) and ``cameras``: a list of ``name``, ``width`` and ``height`` [px],
``intrinsics`` K (3x3), ``camera_to_world`` (4x4; OpenCV camera axes: x right, y down, z forward,
see :mod:`voxposer.perception.observation`), and the file names ``colour``, ``depth``
(``labels``). :class:`RecordedFrames` serves a folder as an
:class:`~voxposer.perception.perceiver.ObservationSource`.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any, Final

import imageio.v3 as iio
import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.perception.observation import CameraFrame, Observation
from voxposer.perception.recorded import RecordedObservations

FORMAT: Final = "voxposer-frames"
VERSION: Final = 1
META_NAME: Final = "frames.json"
#: Depth units a folder may use, with their size [m].
DEPTH_UNITS: Final = {"mm": 1e-3}
_MAX_CODE = 65535  # largest 16-bit value
_CAMERA_NAME = re.compile(r"[A-Za-z0-9_-]+")


def save_frames(obs: Observation, directory: str | Path, *, labels: bool = False,
                gripper_opening_m: float | None = None) -> Path:
    """Write ``obs`` to the folder ``directory`` (created if needed); returns the JSON's path.

    Args:
        obs: the views and robot state.
        labels: also write each view's segmentation channel (ground truth in simulation).
        gripper_opening_m: measured finger distance [m], if known.

    Raises:
        ConfigError: ``directory`` is a file, or a camera name is no plain file-name word.
    """
    out = Path(directory)
    if out.exists() and not out.is_dir():
        raise ConfigError(f"cannot save frames into {out}: it is a file; give a folder")
    out.mkdir(parents=True, exist_ok=True)
    cameras = []
    for frame in obs.cameras:
        if not _CAMERA_NAME.fullmatch(frame.name):
            raise ConfigError(f"camera name {frame.name!r} cannot name a file; use letters, "
                              "digits, '_' and '-'")
        h, w = frame.depth.shape
        entry: dict[str, Any] = {
            "name": frame.name, "width": w, "height": h,
            "intrinsics": np.asarray(frame.intrinsics, float).tolist(),
            "camera_to_world": np.asarray(frame.extrinsics, float).tolist(),
            "colour": f"{frame.name}_colour.png", "depth": f"{frame.name}_depth.png"}
        iio.imwrite(out / entry["colour"], np.asarray(frame.rgb, dtype=np.uint8))
        iio.imwrite(out / entry["depth"], depth_to_code(frame.depth))
        if labels:
            entry["labels"] = f"{frame.name}_labels.png"
            ids = np.clip(np.asarray(frame.object_ids, np.int64) + 1, 0, _MAX_CODE)
            iio.imwrite(out / entry["labels"], ids.astype(np.uint16))
        cameras.append(entry)
    meta = {
        "format": FORMAT, "version": VERSION, "time_s": float(obs.time), "depth_unit": "mm",
        "robot": {"ee_position_m": np.asarray(obs.ee_position, float).tolist(),
                  "ee_quat_xyzw": np.asarray(obs.ee_quat, float).tolist(),
                  "gripper": float(obs.gripper),
                  "gripper_opening_m": None if gripper_opening_m is None
                  else float(gripper_opening_m)},
        "labels": list(obs.label_names) if labels else None,
        "cameras": cameras}
    path = out / META_NAME
    path.write_text(json.dumps(meta, indent=1))
    return path


def depth_to_code(depth: NDArray[np.floating]) -> NDArray[np.uint16]:
    """Depth [m], shape (H, W), as 16-bit millimetres; 0 where there is no reading (not finite,
    not positive, or beyond 65.535 m)."""
    mm = np.asarray(depth, dtype=np.float64) / DEPTH_UNITS["mm"]
    valid = np.isfinite(mm) & (mm > 0) & (mm <= _MAX_CODE)
    return np.where(valid, np.rint(np.where(valid, mm, 0.0)), 0).astype(np.uint16)


def load_frames(directory: str | Path) -> Observation:
    """The observation saved in ``directory`` (:func:`save_frames`, or a camera rig's driver);
    without labels every view's ``object_ids`` is -1 and ``label_names`` empty.

    Raises:
        ConfigError: naming the file and what is wrong (missing, unreadable, a bad matrix
            shape, a resolution that disagrees, an unknown depth unit…).
    """
    return _read(Path(directory))[0]


class RecordedFrames(RecordedObservations):
    """A frames folder as an observation source (a static scene: every ``observe`` returns it).

    Args:
        directory: the folder (see the module docs).

    Attributes:
        directory: the folder read.
        gripper_opening_m: measured finger distance [m] recorded with the frames, or None.
        has_labels: whether the views carry a segmentation channel.
    """

    def __init__(self, directory: str | Path) -> None:
        self.directory = Path(directory)
        observation, meta = _read(self.directory)
        super().__init__(observation)
        opening = meta["robot"].get("gripper_opening_m")
        self.gripper_opening_m = None if opening is None else _number(
            opening, "robot.gripper_opening_m", self.directory / META_NAME, 0.0, 1.0)
        self.has_labels = meta.get("labels") is not None


def _read(directory: Path) -> tuple[Observation, dict[str, Any]]:
    """The observation and the parsed ``frames.json`` of ``directory``."""
    meta_path = directory / META_NAME
    if not directory.is_dir():
        raise ConfigError(f"no frames folder at {directory}")
    if not meta_path.is_file():
        raise ConfigError(f"{meta_path} is missing: a frames folder needs it for the cameras' "
                          "calibration and the robot state (voxposer render --save-frames)")
    try:
        meta = json.loads(meta_path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise ConfigError(f"{meta_path} is not valid JSON: {err}") from err
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise ConfigError(f"{meta_path}: 'format' must be {FORMAT!r}")
    if meta.get("version") != VERSION:
        raise ConfigError(f"{meta_path}: version {meta.get('version')!r} is not supported; "
                          f"this reader knows version {VERSION}")
    unit = meta.get("depth_unit")
    if unit not in DEPTH_UNITS:
        raise ConfigError(f"{meta_path}: depth_unit {unit!r} is not supported; allowed: "
                          f"{', '.join(map(repr, DEPTH_UNITS))} (16-bit PNG)")
    names = meta.get("labels")
    if names is not None and not (isinstance(names, list) and all(isinstance(n, str)
                                                                   for n in names)):
        raise ConfigError(f"{meta_path}: 'labels' must be a list of names or null")
    entries = meta.get("cameras")
    if not isinstance(entries, list) or not entries:
        raise ConfigError(f"{meta_path}: 'cameras' must be a non-empty list of cameras")
    frames = tuple(_camera(e, k, directory, meta_path, DEPTH_UNITS[unit], names)
                   for k, e in enumerate(entries))
    seen = [f.name for f in frames]
    if len(set(seen)) != len(seen):
        raise ConfigError(f"{meta_path}: camera names repeat: {seen}")
    robot = meta.get("robot")
    if not isinstance(robot, dict):
        raise ConfigError(f"{meta_path}: 'robot' (the robot state) is missing")
    quat = _matrix(robot.get("ee_quat_xyzw"), (4,), "robot.ee_quat_xyzw", meta_path)
    if not 0.99 < float(np.linalg.norm(quat)) < 1.01:
        raise ConfigError(f"{meta_path}: robot.ee_quat_xyzw must be a unit quaternion (x, y, z, "
                          f"w); got {quat.tolist()}")
    obs = Observation(
        time=_number(meta.get("time_s", 0.0), "time_s", meta_path, 0.0, np.inf),
        cameras=frames,
        ee_position=_matrix(robot.get("ee_position_m"), (3,), "robot.ee_position_m", meta_path),
        ee_quat=quat / np.linalg.norm(quat),
        gripper=_number(robot.get("gripper"), "robot.gripper", meta_path, 0.0, 1.0),
        label_names=tuple(names or ()))
    return obs, meta


def _camera(entry: Any, k: int, directory: Path, meta_path: Path, unit_m: float,
            names: list[str] | None) -> CameraFrame:
    """Camera ``k`` of ``frames.json``: its entry checked and its images read."""
    need = ["name", "width", "height", "intrinsics", "camera_to_world", "colour", "depth"]
    need += ["labels"] if names is not None else []
    missing = [key for key in need if not isinstance(entry, dict) or key not in entry]
    if missing:
        raise ConfigError(f"{meta_path}: cameras[{k}] lacks {', '.join(missing)}")
    name = str(entry["name"])
    where = f"camera {name!r}"
    size = (_pixels(entry["height"], f"{where} height", meta_path),
            _pixels(entry["width"], f"{where} width", meta_path))
    K = _matrix(entry["intrinsics"], (3, 3), f"{where} intrinsics", meta_path)
    T = _matrix(entry["camera_to_world"], (4, 4), f"{where} camera_to_world", meta_path)
    R = T[:3, :3]
    if not (np.allclose(T[3], [0, 0, 0, 1]) and np.allclose(R.T @ R, np.eye(3), atol=1e-3)
            and np.linalg.det(R) > 0):
        raise ConfigError(f"{meta_path}: {where} camera_to_world must be a rigid transform "
                          "(a rotation, a translation, last row 0 0 0 1)")
    rgb = _image(directory, entry["colour"], where, meta_path, np.uint8, (*size, 3))
    code = _image(directory, entry["depth"], where, meta_path, np.uint16, size)
    depth = np.where(code > 0, code * unit_m, np.inf).astype(np.float32)
    ids = np.full(size, -1, dtype=np.int32)
    if names is not None:
        raw = _image(directory, entry["labels"], where, meta_path, np.uint16, size)
        if int(raw.max()) > len(names):
            raise ConfigError(f"{directory / entry['labels']}: label {int(raw.max()) - 1} has "
                              f"no name; {meta_path} lists {len(names)} labels")
        ids = raw.astype(np.int32) - 1
    return CameraFrame(name, rgb, depth, K, T, ids)


def _image(directory: Path, file: Any, where: str, meta_path: Path, dtype: type,
           shape: tuple[int, ...]) -> NDArray[Any]:
    """The image ``file`` of ``directory``, checked to be ``dtype`` and ``shape`` (rows, cols,
    [channels]) as ``frames.json`` says."""
    if not isinstance(file, str) or Path(file).name != file:
        raise ConfigError(f"{meta_path}: {where}: image {file!r} must be a file name in "
                          f"{directory}")
    path = directory / file
    if not path.is_file():
        raise ConfigError(f"{path} is missing ({meta_path} lists it for {where})")
    try:
        image = np.asarray(iio.imread(path))
    except Exception as err:  # imageio raises many kinds (OSError, ValueError…)
        raise ConfigError(f"{path} is not a readable image: {err}") from err
    kind = "8-bit RGB" if dtype is np.uint8 else "16-bit grey"
    if image.dtype != dtype or image.ndim != len(shape):
        raise ConfigError(f"{path} must be a {kind} PNG; got {image.dtype} with shape "
                          f"{image.shape}")
    if image.shape != shape:
        raise ConfigError(f"{path} is {image.shape[1]}x{image.shape[0]} px but {meta_path} gives "
                          f"{where} {shape[1]}x{shape[0]} px (width x height)")
    return image


def _matrix(value: Any, shape: tuple[int, ...], what: str, meta_path: Path
            ) -> NDArray[np.float64]:
    """``value`` as a finite float array of ``shape``; else ConfigError naming ``what``."""
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        array = np.full(0, np.nan)
    if array.shape != shape or not np.isfinite(array).all():
        dims = f"{shape[0]}x{shape[1]} matrix" if len(shape) > 1 else f"{shape[0]}-vector"
        raise ConfigError(f"{meta_path}: {what} must be a {dims} of finite numbers; got "
                          f"shape {array.shape}")
    return array


def _pixels(value: Any, what: str, meta_path: Path) -> int:
    """``value`` as an image side [px]: an integer >= 1; else ConfigError naming ``what``."""
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ConfigError(f"{meta_path}: {what} must be a whole number of pixels >= 1; got "
                          f"{value!r}")
    return value


def _number(value: Any, what: str, meta_path: Path, lo: float, hi: float) -> float:
    """``value`` as a float in [lo, hi]; else ConfigError naming ``what``."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not lo <= value <= hi:
        raise ConfigError(f"{meta_path}: {what} must be a number in [{lo:g}, {hi:g}]; got "
                          f"{value!r}")
    return float(value)


__all__ = ["DEPTH_UNITS", "FORMAT", "META_NAME", "VERSION", "RecordedFrames", "depth_to_code",
           "load_frames", "save_frames"]
