"""U-Net + MP training data: the target is the reference programs' composed cost, seeds are dev
only, and a resumed run adds only the new seeds."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from voxposer.bench.methods import get_method
from voxposer.bench.task import reset_episode
from voxposer.bench.tasks import get_task
from voxposer.bench.unet_data import DataConfig, episode_sample, generate, parse_seeds
from voxposer.control import ExecutorConfig
from voxposer.errors import ConfigError
from voxposer.lmp.handoff import RecordingHandler
from voxposer.lmp.runtime import LMPRuntime
from voxposer.pipeline import Embodiment
from voxposer.unet.dataset import MANIFEST, load_dataset
from voxposer.valuemaps.cost import compose_cost_map

SEED = 3  # a fixed dev seed


def _independent_cost(world, task_name: str, seed: int) -> tuple[np.ndarray, str]:
    """The first sub-task's cost map composed here: the reference programs' maps evaluated
    once (no robot), then :func:`compose_cost_map` with the end-effector planner's settings."""
    task = get_task(task_name)
    setup = reset_episode(task, world, "seen", seed)
    backend = get_method("voxposer").reference_backend(task, setup.attributes)
    body = Embodiment.simulated(world)
    handler = RecordingHandler()
    LMPRuntime(body.scene, backend, handler).run(setup.instruction)
    first = handler.evaluated[0]
    name = str(first["movable"]["name"])
    cmap = compose_cost_map(
        body.perceiver.grid, first["affordance_map"], world.get_ee_pose()[0],
        avoidance_map=first.get("avoidance_map"),
        occupancy=body.perceiver.scene_occupancy(name, holding=False),
        config=ExecutorConfig().ee_planner.cost)
    return cmap.cost, setup.instruction


@pytest.mark.parametrize("task", ["move_to_region", "move_to_pos_min_distance"])
def test_target_is_the_reference_programs_composed_cost(world, task: str) -> None:
    expected, instruction = _independent_cost(world, task, SEED)
    sample = episode_sample(world, task, SEED)
    assert sample.instruction == instruction and sample.entity == "gripper"
    assert sample.cost.shape == expected.shape == (50, 50, 50)
    np.testing.assert_array_equal(sample.cost, expected)
    assert sample.cost_scale == 3.0
    assert sample.occupancy.shape == (50, 50, 50) and sample.occupancy.sum() > 100
    assert sample.colour[sample.occupancy == 0].max() == 0


def test_resume_adds_only_the_new_seeds(world, tmp_path: Path) -> None:
    config = DataConfig(("move_to_region",), (0,), shard_size=4)
    first = generate(tmp_path, world, config)
    assert first["done"] == {"move_to_region": [0]}
    assert [s["count"] for s in first["shards"]] == [1]
    with pytest.raises(ConfigError, match="add --resume"):
        generate(tmp_path, world, config)
    calls: list[tuple[str, int]] = []
    second = generate(tmp_path, world, DataConfig(("move_to_region",), (0, 1), shard_size=4),
                      resume=True, on_episode=lambda t, s, _: calls.append((t, s)))
    assert calls == [("move_to_region", 1)]
    assert second["done"] == {"move_to_region": [0, 1]}
    assert [s["count"] for s in second["shards"]] == [1, 1]
    manifest = json.loads((tmp_path / MANIFEST).read_text())
    assert manifest["grid_shape"] == [50, 50, 50]
    assert manifest["vocabulary"][:2] == ["<pad>", "<unk>"]
    data = load_dataset(tmp_path)
    assert list(data.seed) == [0, 1] and data.cost.shape == (2, 50, 50, 50)
    assert set(manifest["vocabulary"][2:]) >= {"move", "to", "the", "side", "table"}


def test_test_seeds_are_refused() -> None:
    with pytest.raises(ConfigError, match="not a dev seed"):
        parse_seeds("100000-100004", 5)
    with pytest.raises(ConfigError, match="not a dev seed"):
        DataConfig(("move_to_region",), (100_000,))
    assert parse_seeds("dev", 3) == [0, 1, 2]
    assert parse_seeds("0,5,7-9", 4) == [0, 5, 7, 8]


def test_samples_carry_the_scene_in_colour(tmp_path: Path) -> None:
    """The U-Net tells the pink block from the green one by colour: the observation voxels hold
    the views' RGB, not the black of a depth-only render."""
    from voxposer.envs import TabletopWorld

    world = TabletopWorld()
    try:
        sample = episode_sample(world, "move_to_region", 3)
    finally:
        world.close()
    filled = sample.occupancy.astype(bool)
    assert filled.any() and sample.colour[filled].max() > 100
    assert len(np.unique(sample.colour[filled].reshape(-1, 3), axis=0)) > 5
