"""Registering the cameras against each other: miscalibrated views of the shared world are made
to agree, exact views are left alone, and a source keeps one correction per episode."""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest
from tests.calibration import disagreement_mm, miscalibrated

from voxposer.envs import SceneLayout, TabletopWorld
from voxposer.errors import ConfigError
from voxposer.perception import Observation
from voxposer.perception.surface_registration import RegistrationConfig, register_clouds
from voxposer.perception.view_registration import RegisteredObservationSource, register_views


@pytest.fixture
def scene(world: TabletopWorld) -> Observation:
    world.reset(np.random.default_rng(3), SceneLayout())
    return world.observe(rgb=False)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_miscalibrated_cameras_are_made_to_agree(
        world: TabletopWorld, scene: Observation, seed: int) -> None:
    seen = miscalibrated(scene, seed)
    before = disagreement_mm(scene, seen)
    corrections = register_views(seen.cameras, world.grid)
    after = disagreement_mm(scene, seen, corrections)
    assert before > 10.0, "the drawn calibration error should smear the views"
    assert after < 5.5 and after < 0.4 * before, f"disagreement {before:.1f} → {after:.1f} mm"


def test_exact_cameras_stay_within_the_registration_floor(
        world: TabletopWorld, scene: Observation) -> None:
    """The tops' centroids are biased a millimetre or two per view (sampling of their edges):
    exact views come out a few millimetres apart (5.2 mm here, the largest camera pair, over
    the whole workspace), no further."""
    corrections = register_views(scene.cameras, world.grid)
    assert disagreement_mm(scene, scene, corrections) < 6.0


def test_a_correction_beyond_the_configured_bound_keeps_the_calibration(
        world: TabletopWorld, scene: Observation) -> None:
    seen = miscalibrated(scene, 0)
    tight = RegistrationConfig(max_rotation_deg=0.01, max_translation_m=0.0001)
    corrections = register_views(seen.cameras, world.grid, tight)
    assert all(np.array_equal(c, np.eye(4)) for c in corrections.values())


def test_one_camera_or_an_empty_view_registers_nothing() -> None:
    rng = np.random.default_rng(0)
    assert np.array_equal(register_clouds([rng.random((500, 3))])[0], np.eye(4))
    out = register_clouds([rng.random((500, 3)), np.zeros((0, 3))])
    assert all(np.array_equal(m, np.eye(4)) for m in out)


class _Replay:
    """An observation source serving given observations one after another."""

    def __init__(self, observations: list[Observation]) -> None:
        self.observations = observations
        self.object_names = ("table",)

    def observe(self, *, rgb: bool = True, labels: bool = True) -> Observation:
        return self.observations.pop(0)


def test_the_source_registers_once_per_episode_and_keeps_frames(
        world: TabletopWorld, scene: Observation, monkeypatch: pytest.MonkeyPatch) -> None:
    first = miscalibrated(scene, 0)
    later = replace(first, time=first.time + 1.0,
                    cameras=(first.cameras[0],) + tuple(replace(f) for f in first.cameras[1:]))
    reset = replace(miscalibrated(scene, 1), time=0.0)
    calls: list[int] = []
    import voxposer.perception.view_registration as module
    real = module.register_views
    monkeypatch.setattr(module, "register_views",
                        lambda *a, **k: calls.append(1) or real(*a, **k))
    source = RegisteredObservationSource(_Replay([first, later, reset]), world.grid)
    a = source.observe()
    corrections = dict(source.corrections)
    b = source.observe()
    assert len(calls) == 1 and source.corrections == corrections
    assert b.cameras[0] is a.cameras[0], "an unchanged frame is served as the same object"
    for raw, served in zip(later.cameras, b.cameras, strict=True):
        assert served.depth is raw.depth
        np.testing.assert_allclose(served.extrinsics, corrections[raw.name] @ raw.extrinsics)
    source.observe()
    assert len(calls) == 2, "the time went back: a new episode is registered again"


def test_bad_config_names_the_field() -> None:
    with pytest.raises(ConfigError, match=re.escape("RegistrationConfig.rounds")):
        RegistrationConfig(rounds=0)
    with pytest.raises(ConfigError, match=re.escape("RegistrationConfig.voxel_m")):
        RegistrationConfig(voxel_m=-1.0)
    with pytest.raises(ConfigError, match=re.escape("RegistrationConfig.patch_min_height_m")):
        RegistrationConfig(patch_min_height_m=0.2)  # above the 0.12 m maximum


def test_a_scene_with_too_few_raised_tops_keeps_the_calibration(world: TabletopWorld) -> None:
    """One block and a cabinet: the left–right offset is not pinned, so nothing is moved."""
    from voxposer.bench.task import reset_episode
    from voxposer.bench.tasks import TASKS

    reset_episode(TASKS["close_drawer"], world, "seen", 0)
    assert sum("block" in n for n in world.object_names) == 1
    seen = miscalibrated(world.observe(rgb=False), 0)
    corrections = register_views(seen.cameras, world.grid)
    assert all(np.array_equal(c, np.eye(4)) for c in corrections.values())
