"""Sensor realism: each effect does what its config says, on synthetic views (no simulator,
except the last tests, which build the pipeline's perceivers on the shared world)."""

from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np
import pytest

from voxposer.envs import TabletopWorld
from voxposer.errors import ConfigError
from voxposer.perception import (
    CameraFrame,
    NoisyObservationSource,
    Observation,
    SegmentationPerceiver,
    SensorNoiseConfig,
    add_sensor_noise,
    backproject,
)
from voxposer.perception.colour_depth import ColourDepthPerceiver
from voxposer.perception.sensor_noise import EFFECTS, corrupt_mask
from voxposer.perception.view_registration import RegisteredObservationSource
from voxposer.pipeline import PERCEPTIONS, check_perception, simulated_perceiver

H, W = 120, 160
K = np.array([[150.0, 0.0, (W - 1) / 2], [0.0, 150.0, (H - 1) / 2], [0.0, 0.0, 1.0]])
TYPICAL = SensorNoiseConfig()


def _frame(depth: float | np.ndarray = 1.0, rgb: int | np.ndarray = 200, name: str = "cam",
           ids: np.ndarray | None = None) -> CameraFrame:
    d = np.broadcast_to(np.asarray(depth, np.float32), (H, W)).astype(np.float32)
    colour = np.broadcast_to(np.asarray(rgb, np.uint8)[..., None], (H, W, 3)).astype(np.uint8)
    return CameraFrame(name, colour, d, K.copy(), np.eye(4),
                       np.full((H, W), -1, np.int32) if ids is None else ids)


def _obs(*frames: CameraFrame, time: float = 0.0) -> Observation:
    return Observation(time, frames or (_frame(),), np.zeros(3), np.array([0.0, 0, 0, 1]), 0.0,
                       ("a", "b", "c", "d"))


def _same(a: Observation, b: Observation) -> bool:
    return all(fa.name == fb.name and all(
        np.array_equal(getattr(fa, k), getattr(fb, k), equal_nan=k == "depth")
        for k in ("rgb", "depth", "intrinsics", "extrinsics", "object_ids"))
        for fa, fb in zip(a.cameras, b.cameras, strict=True))


@pytest.mark.parametrize("z", [0.5, 1.0, 1.5])
def test_depth_noise_std_grows_with_the_square_of_depth(z: float) -> None:
    noisy = add_sensor_noise(_obs(_frame(z)), TYPICAL.only("depth_noise"),
                             np.random.default_rng(0)).cameras[0].depth
    expected = TYPICAL.depth_noise_base_m + TYPICAL.depth_noise_quadratic_per_m * z * z
    assert float(np.std(noisy)) == pytest.approx(expected, rel=0.03)
    assert float(np.mean(noisy)) == pytest.approx(z, abs=3 * expected / math.sqrt(H * W))


def test_missing_depth_at_an_edge_and_on_a_dark_patch_only() -> None:
    depth = np.full((H, W), 1.0, np.float32)
    depth[:, 80:] = 0.8  # a 20 cm step between columns 79 and 80
    rgb = np.full((H, W), 200, np.uint8)
    rgb[10:30, 10:40] = 10  # a dark patch, far from the edge
    cfg = TYPICAL.only("edge_dropout", "dark_dropout")
    missing = np.isnan(add_sensor_noise(_obs(_frame(depth, rgb)), cfg,
                                        np.random.default_rng(1)).cameras[0].depth)
    assert 0.3 < missing[:, 79:81].mean() < 0.7  # about edge_dropout_p of the edge's pixels
    assert 0.3 < missing[10:30, 10:40].mean() < 0.7  # about dark_dropout_p of the patch
    bright_flat = np.ones((H, W), bool)
    bright_flat[:, 79:81] = bright_flat[10:30, 10:40] = False
    assert not missing[bright_flat].any()
    certain = add_sensor_noise(_obs(_frame(depth, rgb)), SensorNoiseConfig(
        edge_dropout_p=1.0, dark_dropout_p=1.0).only("edge_dropout", "dark_dropout"),
        np.random.default_rng(1)).cameras[0].depth
    assert np.isnan(certain[:, 79:81]).all() and np.isnan(certain[10:30, 10:40]).all()


def test_background_keeps_its_inf_and_edges_against_it_lose_depth() -> None:
    depth = np.full((H, W), 1.0, np.float32)
    depth[:, :40] = np.inf
    out = add_sensor_noise(_obs(_frame(depth)), SensorNoiseConfig(edge_dropout_p=1.0),
                           np.random.default_rng(2)).cameras[0].depth
    assert np.isposinf(out[:, :40]).all() and np.isnan(out[:, 40]).all()


def test_translation_error_moves_a_reconstructed_point_by_its_size() -> None:
    cfg = SensorNoiseConfig(calibration_rotation_deg=0.0).only("calibration")
    for seed in range(5):
        frame = add_sensor_noise(_obs(), cfg, np.random.default_rng(seed)).cameras[0]
        moved = backproject(frame.depth, K, frame.extrinsics) - backproject(frame.depth, K,
                                                                             np.eye(4))
        np.testing.assert_allclose(np.linalg.norm(moved, axis=-1),
                                   cfg.calibration_translation_m, rtol=1e-5)


def test_rotation_error_has_its_angle_and_moves_a_point_1m_away_by_about_d_theta() -> None:
    cfg = SensorNoiseConfig(calibration_translation_m=0.0).only("calibration")
    shifts = []
    for seed in range(200):
        ext = add_sensor_noise(_obs(), cfg, np.random.default_rng(seed)).cameras[0].extrinsics
        angle = math.degrees(math.acos(np.clip((np.trace(ext[:3, :3]) - 1) / 2, -1, 1)))
        assert angle == pytest.approx(cfg.calibration_rotation_deg, abs=1e-3)
        shifts.append(float(np.linalg.norm(ext[:3, :3] @ [0, 0, 1.0] - [0, 0, 1.0])))
    d_theta = math.radians(cfg.calibration_rotation_deg)  # 1 m × θ
    assert max(shifts) <= d_theta * 1.0001
    # about a uniformly random axis, the mean shift is π/4 of d·θ
    assert np.mean(shifts) == pytest.approx(d_theta * math.pi / 4, rel=0.12)


def test_mask_erosion_and_dilation_move_the_boundary_by_k_pixels() -> None:
    ids = np.full((H, W), -1, np.int32)
    ids[40:60, 50:70] = 3
    rng = np.random.default_rng(0)
    eroded = corrupt_mask(ids, -2, 0.0, rng)
    assert np.array_equal(np.argwhere(eroded == 3).min(0), [42, 52])
    assert np.array_equal(np.argwhere(eroded == 3).max(0), [57, 67])
    assert (eroded == 3).sum() == 16 * 16 and set(np.unique(eroded)) == {-1, 3}
    dilated = corrupt_mask(ids, 2, 0.0, rng)
    assert (dilated == 3).sum() == 24 * 24
    assert np.array_equal(corrupt_mask(ids, 0, 1.0, rng), np.full((H, W), -1))
    assert np.array_equal(corrupt_mask(ids, 0, 0.0, rng), ids)


def test_mask_corruption_only_touches_the_label_channel() -> None:
    ids = np.full((H, W), -1, np.int32)
    ids[40:60, 50:70] = 1
    obs = _obs(_frame(ids=ids))
    cfg = SensorNoiseConfig(mask_boundary_px=-3, mask_miss_p=0.0).only("mask_corruption")
    out = add_sensor_noise(obs, cfg, np.random.default_rng(0)).cameras[0]
    assert (out.object_ids == 1).sum() == 14 * 14  # eroded by 3 on every side
    assert out.depth is obs.cameras[0].depth and out.extrinsics is obs.cameras[0].extrinsics


def test_disabled_effects_leave_the_observation_bit_identical() -> None:
    depth = np.full((H, W), 1.0, np.float32)
    depth[:, 80:] = np.inf
    obs = _obs(_frame(depth, 5), _frame(0.7, name="other"))
    assert _same(add_sensor_noise(obs, SensorNoiseConfig.disabled(),
                                  np.random.default_rng(0)), obs)
    # the dark-dropout switch alone: an image with no colour rendered (all black) is skipped
    blank = _obs(_frame(depth, 0))
    assert _same(add_sensor_noise(blank, TYPICAL.only("dark_dropout"),
                                  np.random.default_rng(0)), blank)


def test_the_input_is_never_modified() -> None:
    ids = np.full((H, W), -1, np.int32)
    ids[40:60, 50:70] = 2
    obs = _obs(_frame(np.linspace(0.5, 1.5, W, dtype=np.float32)[None, :].repeat(H, 0),
                      ids=ids))
    before = _obs(*(CameraFrame(f.name, f.rgb.copy(), f.depth.copy(), f.intrinsics.copy(),
                                f.extrinsics.copy(), f.object_ids.copy()) for f in obs.cameras))
    noisy = add_sensor_noise(obs, TYPICAL, np.random.default_rng(3))
    assert _same(obs, before) and not _same(noisy, obs)


def test_same_generator_state_gives_the_same_noisy_observation() -> None:
    depth = np.full((H, W), 1.0, np.float32)
    depth[:, 80:] = 0.8
    obs = _obs(_frame(depth, ids=np.where(depth > 0.9, 1, 2).astype(np.int32)),
               _frame(0.9, name="other"))
    a, b = (add_sensor_noise(obs, TYPICAL, np.random.default_rng(11)) for _ in range(2))
    assert _same(a, b)
    assert not _same(a, add_sensor_noise(obs, TYPICAL, np.random.default_rng(12)))


class _Clock:
    """A fake observation source whose time the test sets."""

    object_names = ("a",)

    def __init__(self) -> None:
        self.time = 0.0
        self._obs = _obs(time=0.0)

    def observe(self, *, rgb: bool = True, labels: bool = True) -> Observation:
        if self._obs.time != self.time:
            self._obs = _obs(time=self.time)
        return self._obs


def test_noisy_source_keeps_calibration_within_an_episode_and_redraws_on_reset() -> None:
    clock = _Clock()
    source = NoisyObservationSource(clock, TYPICAL, seed=5)
    first = source.observe()
    assert source.observe(rgb=False) is first  # one noisy view per instant
    clock.time = 0.5
    later = source.observe()
    assert np.array_equal(later.cameras[0].extrinsics, first.cameras[0].extrinsics)
    assert not np.array_equal(later.cameras[0].depth, first.cameras[0].depth, equal_nan=True)
    clock.time = 0.1  # the world was reset
    after_reset = source.observe()
    assert source.episode == 1
    assert not np.allclose(after_reset.cameras[0].extrinsics, first.cameras[0].extrinsics)
    replay = NoisyObservationSource(_Clock(), TYPICAL, seed=5)
    assert _same(replay.observe(), first)
    with pytest.raises(ConfigError, match=r"seed.*-1"):
        NoisyObservationSource(clock, TYPICAL, seed=-1)


@pytest.mark.parametrize(("field", "value"), [
    ("depth_noise_base_m", -0.001), ("depth_noise_quadratic_per_m", math.nan),
    ("edge_dropout_p", 1.5), ("dark_intensity", 2.0), ("mask_miss_p", -0.1),
    ("edge_band_px", 0), ("mask_boundary_px", 1.5), ("calibration_rotation_deg", 45.0),
    ("calibration", "yes"), ("edge_jump_m", "3 cm"),
])
def test_bad_config_values_name_the_field_and_value(field: str, value: object) -> None:
    with pytest.raises(ConfigError, match=re.escape(f"SensorNoiseConfig.{field}") + ".*"
                       + re.escape(repr(value))):
        SensorNoiseConfig(**{field: value})  # type: ignore[arg-type]


def test_only_lists_the_effects_when_told_an_unknown_one() -> None:
    with pytest.raises(ConfigError, match=", ".join(EFFECTS)):
        TYPICAL.only("blur")


@pytest.mark.parametrize("mode", PERCEPTIONS)
def test_every_perception_mode_builds_its_perceiver(fresh: TabletopWorld, mode: str) -> None:
    perceiver = simulated_perceiver(fresh, mode)
    kind = ColourDepthPerceiver if mode.startswith("colour-depth") else SegmentationPerceiver
    assert isinstance(perceiver, kind)
    source = perceiver.source
    if mode.endswith("-noisy"):  # the sensor model, its cameras registered against each other
        assert isinstance(source, RegisteredObservationSource)
        assert isinstance(source.source, NoisyObservationSource)
        unregistered = simulated_perceiver(fresh, mode, register=False).source
        assert isinstance(unregistered, NoisyObservationSource)
        calibrated = simulated_perceiver(fresh, mode, noise=SensorNoiseConfig(calibration=False))
        assert isinstance(calibrated.source, NoisyObservationSource)
    else:
        assert not isinstance(source, NoisyObservationSource | RegisteredObservationSource)


def test_noisy_ground_truth_sees_noisy_views_deterministically(fresh: TabletopWorld) -> None:
    a = simulated_perceiver(fresh, "ground-truth-noisy").observe()
    b = simulated_perceiver(fresh, "ground-truth-noisy").observe()
    clean = fresh.observe()
    assert _same(a, b) and not _same(a, clean)
    assert np.isnan(a.cameras[0].depth).any() and not np.isnan(clean.cameras[0].depth).any()


def test_an_unknown_perception_lists_the_allowed_ones(world: TabletopWorld) -> None:
    with pytest.raises(ConfigError, match=re.escape(", ".join(PERCEPTIONS))):
        simulated_perceiver(world, "noisy")
    assert check_perception("colour-depth-noisy") == "colour-depth-noisy"


def test_the_cli_accepts_and_lists_every_perception_mode(capsys: pytest.CaptureFixture[str]
                                                         ) -> None:
    from voxposer.cli import build_parser
    from voxposer.cli.run import PERCEPTION_CHOICES

    assert PERCEPTION_CHOICES == (*PERCEPTIONS, "open-vocab")
    parser = build_parser()
    for mode in PERCEPTIONS:
        assert parser.parse_args(["run", "push it", "--perception", mode]).perception == mode
        assert parser.parse_args(["bench", "--perception", mode]).perception == mode
    with pytest.raises(SystemExit):
        parser.parse_args(["bench", "--help"])
    assert "colour-depth-noisy" in capsys.readouterr().out


class _Streaming:
    """A fake source of two cameras: "a" renews its frame at every new time, "b" only when
    the test says (a camera whose next frame is not due)."""

    object_names = ("a",)

    def __init__(self) -> None:
        self.time = 0.0
        self.frames = {"a": _frame(name="a"), "b": _frame(0.8, name="b")}
        self._obs = _obs(*self.frames.values(), time=0.0)

    def renew(self, name: str) -> None:
        self.frames[name] = replace(self.frames[name])

    def observe(self, *, rgb: bool = True, labels: bool = True) -> Observation:
        if self._obs.time != self.time:
            self.frames["a"] = replace(self.frames["a"])
            self._obs = _obs(*self.frames.values(), time=self.time)
        return self._obs


def test_a_frame_not_renewed_keeps_its_noise_and_a_new_one_is_noised_afresh() -> None:
    raw = _Streaming()
    source = NoisyObservationSource(raw, TYPICAL, seed=5)
    first = source.observe()
    whole = add_sensor_noise(raw.observe(), TYPICAL,
                             np.random.default_rng([5, 0, 1, 0]), source._calibration)
    assert _same(first, whole)  # every frame new: the whole observation's noise, as before
    raw.time = 0.2
    second = source.observe()
    assert second.cameras[1] is first.cameras[1]  # "b" not renewed: the same noisy image
    assert not np.array_equal(second.cameras[0].depth, first.cameras[0].depth, equal_nan=True)
    raw.renew("b")
    raw.time = 0.4
    third = source.observe()
    assert third.cameras[1] is not first.cameras[1]
    assert not np.array_equal(third.cameras[1].depth, first.cameras[1].depth, equal_nan=True)
    replay = _Streaming()
    again = NoisyObservationSource(replay, TYPICAL, seed=5)
    for t in (0.0, 0.2):  # the same frames at the same times: the same noise
        replay.time = t
        again.observe()
    replay.renew("b")
    replay.time = 0.4
    assert _same(again.observe(), third)
