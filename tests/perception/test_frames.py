"""Recorded frames (a folder of PNGs and frames.json): the round trip keeps the observation, and
every bad folder is one error naming the file at fault."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from voxposer.errors import ConfigError
from voxposer.perception.frames import (
    META_NAME,
    RecordedFrames,
    depth_to_code,
    load_frames,
    save_frames,
)
from voxposer.perception.observation import CameraFrame, Observation
from voxposer.perception.perceiver import ObservationSource

H, W = 24, 32
NAMES = ("table", "blue block", "green block")


def _frame(name: str, rng: np.random.Generator) -> CameraFrame:
    depth = rng.uniform(0.3, 3.0, (H, W)).astype(np.float32)
    depth[:3] = np.inf  # background
    K = np.array([[40.0, 0.0, W / 2 - 0.5], [0.0, 40.0, H / 2 - 0.5], [0.0, 0.0, 1.0]])
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("xyz", rng.uniform(-1, 1, 3)).as_matrix()
    T[:3, 3] = rng.uniform(-1, 1, 3)
    return CameraFrame(name, rng.integers(0, 256, (H, W, 3), dtype=np.uint8), depth, K, T,
                       rng.integers(-1, len(NAMES), (H, W)).astype(np.int32))


def _observation(seed: int = 0) -> Observation:
    rng = np.random.default_rng(seed)
    quat = Rotation.from_euler("z", 0.3).as_quat()
    return Observation(time=1.25, cameras=(_frame("cam_a", rng), _frame("cam_b", rng)),
                       ee_position=np.array([-0.2, 0.05, 0.3]), ee_quat=quat, gripper=1.0,
                       label_names=NAMES)


def test_round_trip_keeps_the_observation_with_labels(tmp_path: Path) -> None:
    obs = _observation()
    save_frames(obs, tmp_path / "f", labels=True, gripper_opening_m=0.05)
    back = load_frames(tmp_path / "f")
    assert [c.name for c in back.cameras] == ["cam_a", "cam_b"]
    for a, b in zip(obs.cameras, back.cameras, strict=True):
        np.testing.assert_array_equal(b.rgb, a.rgb)
        np.testing.assert_array_equal(b.intrinsics, a.intrinsics)
        np.testing.assert_array_equal(b.extrinsics, a.extrinsics)
        np.testing.assert_array_equal(b.object_ids, a.object_ids)
        assert b.depth.dtype == np.float32
        np.testing.assert_array_equal(np.isinf(b.depth), np.isinf(a.depth))
        finite = np.isfinite(a.depth)
        error = np.abs(b.depth[finite] - a.depth[finite])
        assert error.max() <= 0.0005 + 1e-6  # 1 mm steps
        assert error.max() > 1e-5  # the format quantises: this is not a lossless copy
    np.testing.assert_array_equal(back.ee_position, obs.ee_position)
    np.testing.assert_allclose(back.ee_quat, obs.ee_quat, atol=1e-12)
    assert (back.time, back.gripper, back.label_names) == (1.25, 1.0, NAMES)
    source = RecordedFrames(tmp_path / "f")
    assert isinstance(source, ObservationSource)
    assert source.observe(rgb=False) is source.observation
    assert source.has_labels and source.gripper_opening_m == 0.05
    assert set(source.object_names) <= set(NAMES) and "blue block" in source.object_names


def test_without_labels_no_segmentation_is_written_or_read(tmp_path: Path) -> None:
    save_frames(_observation(), tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "cam_a_colour.png", "cam_a_depth.png", "cam_b_colour.png", "cam_b_depth.png", META_NAME]
    meta = json.loads((tmp_path / META_NAME).read_text())
    assert meta["labels"] is None and meta["depth_unit"] == "mm" and meta["version"] == 1
    assert np.asarray(meta["cameras"][0]["intrinsics"]).shape == (3, 3)
    assert np.asarray(meta["cameras"][0]["camera_to_world"]).shape == (4, 4)
    back = load_frames(tmp_path)
    assert back.label_names == () and all((c.object_ids == -1).all() for c in back.cameras)
    source = RecordedFrames(tmp_path)
    assert not source.has_labels and source.object_names == ()
    assert source.gripper_opening_m is None


def test_depth_code_is_millimetres_with_zero_for_no_reading() -> None:
    code = depth_to_code(np.array([[0.0, 0.0014, 1.2346, np.inf, np.nan, -1.0, 70.0]]))
    assert code.dtype == np.uint16
    assert code.tolist() == [[0, 1, 1235, 0, 0, 0, 0]]


def _edit_meta(edit: Callable[[dict], None]) -> Callable[[Path], None]:
    def apply(folder: Path) -> None:
        meta = json.loads((folder / META_NAME).read_text())
        edit(meta)
        (folder / META_NAME).write_text(json.dumps(meta))
    return apply


def _set_camera(key: str, value: object) -> Callable[[Path], None]:
    return _edit_meta(lambda m: m["cameras"][0].__setitem__(key, value))


BAD: dict[str, tuple[Callable[[Path], None], str, tuple[str, ...]]] = {
    "no json": (lambda f: (f / META_NAME).unlink(), META_NAME, ("missing", "calibration")),
    "not json": (lambda f: (f / META_NAME).write_text("{cameras: ["), META_NAME,
                 ("not valid JSON",)),
    "no colour": (lambda f: (f / "cam_a_colour.png").unlink(), "cam_a_colour.png",
                  ("missing", "'cam_a'")),
    "no depth": (lambda f: (f / "cam_b_depth.png").unlink(), "cam_b_depth.png", ("missing",)),
    "depth smaller than colour": (
        lambda f: iio.imwrite(f / "cam_a_depth.png", np.zeros((H // 2, W), np.uint16)),
        "cam_a_depth.png", (f"{W}x{H // 2} px", f"{W}x{H} px")),
    "json size wrong": (_set_camera("width", W + 1), "cam_a_colour.png",
                        (f"{W}x{H} px", f"{W + 1}x{H} px")),
    "8-bit depth": (lambda f: iio.imwrite(f / "cam_a_depth.png", np.zeros((H, W), np.uint8)),
                    "cam_a_depth.png", ("16-bit",)),
    "depth unit": (_edit_meta(lambda m: m.__setitem__("depth_unit", "m")), META_NAME,
                   ("depth_unit 'm'", "'mm'")),
    "intrinsics 3x4": (_set_camera("intrinsics", np.zeros((3, 4)).tolist()), META_NAME,
                       ("intrinsics", "3x3", "(3, 4)")),
    "extrinsics 3x4": (_set_camera("camera_to_world", np.eye(4)[:3].tolist()), META_NAME,
                       ("camera_to_world", "4x4", "(3, 4)")),
    "extrinsics not rigid": (_set_camera("camera_to_world", (2 * np.eye(4)).tolist()),
                             META_NAME, ("rigid",)),
    "no calibration": (_edit_meta(lambda m: m["cameras"][1].pop("intrinsics")), META_NAME,
                       ("cameras[1]", "intrinsics")),
    "no robot": (_edit_meta(lambda m: m.pop("robot")), META_NAME, ("robot",)),
    "label without name": (_edit_meta(lambda m: m.__setitem__("labels", ["table"])),
                           "_labels.png", ("has no name",)),
}


@pytest.mark.parametrize("case", list(BAD))
def test_a_bad_folder_is_one_error_naming_the_file(tmp_path: Path, case: str) -> None:
    save_frames(_observation(), tmp_path, labels=True)
    break_it, file, words = BAD[case]
    break_it(tmp_path)
    with pytest.raises(ConfigError) as info:
        load_frames(tmp_path)
    message = str(info.value)
    assert file in message, message
    for word in words:
        assert word in message, message


def test_saving_into_a_file_or_a_missing_folder_is_refused(tmp_path: Path) -> None:
    (tmp_path / "taken").write_text("x")
    with pytest.raises(ConfigError, match="it is a file"):
        save_frames(_observation(), tmp_path / "taken")
    with pytest.raises(ConfigError, match=r"no frames folder at .*absent"):
        load_frames(tmp_path / "absent")
