"""The U-Net + MP method: the predicted cost goes to the same planner and executor as VoxPoser's.

With the true composed cost as the "prediction" (:func:`_oracle`, a test double monkeypatched
over the U-Net's forward pass; the cost is the training target of the episode,
:func:`voxposer.bench.unet_data.episode_sample`) a benchmark episode succeeds — the plumbing
predicted cost → planner → executor (the hand, or the pushing loop for a block) works; with a
constant, uninformative prediction it fails; with a tiny checkpoint trained here for a few steps
on one dev-seed sample it runs and records what ran. A multi-step task stops after the first
sub-task, saying so.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from voxposer.bench.episode import EpisodeJob, run_episode
from voxposer.bench.methods import NO_LLM, UNET_MP
from voxposer.bench.tasks import TASKS, get_task
from voxposer.bench.unet_data import episode_sample
from voxposer.bench.unet_method import PredictedCostPlanner, first_subtask
from voxposer.control import ExecutorConfig
from voxposer.pipeline import Embodiment
from voxposer.unet.dataset import Sample

torch = pytest.importorskip("torch")
torch.set_num_threads(1)

from voxposer.unet import predict  # noqa: E402 - after the torch check
from voxposer.unet.checkpoint import load_checkpoint, save_checkpoint  # noqa: E402
from voxposer.unet.model import UNetConfig  # noqa: E402
from voxposer.unet.train import batch_from_arrays, make_model, train_step  # noqa: E402
from voxposer.unet.vocabulary import Vocabulary, tokenise  # noqa: E402

TASK, SEED = "move_to_region", 3  # an end-effector task, a dev seed
MAX_TIME_S = 20.0


@pytest.fixture(scope="module")
def sample(world: Any) -> Sample:
    """The training triple of the end-effector episode (its cost: the true composed cost)."""
    return episode_sample(world, TASK, SEED)


@pytest.fixture(scope="module")
def checkpoint(sample: Sample, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A tiny U-Net on the planning grid (50³), trained 3 steps on one dev-seed sample."""
    vocabulary = Vocabulary.build([sample.instruction])
    config = UNetConfig(base_channels=4, depth=1, embed_dim=4)
    model = make_model(config, vocabulary, sample.cost.shape, np.random.default_rng(0))
    batch = batch_from_arrays(sample.occupancy[None], sample.colour[None], sample.cost[None],
                              [sample.instruction], vocabulary, config, sample.cost_scale)
    optimiser = torch.optim.Adam(model.parameters(), lr=1e-2)
    for _ in range(3):
        train_step(model, optimiser, batch)
    path = tmp_path_factory.mktemp("unet") / "model.pt"
    return save_checkpoint(path, model, vocabulary, sample.cost.shape, sample.cost_scale)


def _oracle(cost: np.ndarray) -> Any:
    """A double of :func:`voxposer.unet.predict.predict_cost` that ignores the checkpoint and
    the observation and "predicts" ``cost``."""
    def predict_cost(checkpoint: Any, observation: Any, instruction: str) -> np.ndarray:
        return np.asarray(cost, dtype=np.float32)
    return predict_cost


def _episode(world: Any, checkpoint: Path, task: str = TASK,
             instructions: str = "seen") -> dict[str, Any]:
    job = EpisodeJob(task, "seen", SEED, method=UNET_MP, llm=NO_LLM, max_time_s=MAX_TIME_S,
                     seed_set="dev", unet_checkpoint=str(checkpoint), instructions=instructions)
    return run_episode(job, world).to_json()


def test_the_true_cost_as_prediction_succeeds(world, sample: Sample, checkpoint: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(predict, "predict_cost", _oracle(sample.cost))
    rec = _episode(world, checkpoint)
    assert rec["error"] is None and rec["program_error"] is None, rec["reason"]
    assert rec["success"], rec["reason"]
    assert rec["method"] == UNET_MP and rec["llm"] == NO_LLM and rec["llm_calls"] == 0


def test_a_paraphrased_instruction_reaches_the_unet_and_its_cost_is_followed(
        world, sample: Sample, checkpoint: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The U-Net's unseen instructions: the paraphrase split's wording is what it is asked
    (words it never saw are its unknown token), and the planner follows what it predicts."""
    asked: list[str] = []
    oracle = _oracle(sample.cost)

    def predict_cost(checkpoint: Any, observation: Any, instruction: str) -> np.ndarray:
        asked.append(instruction)
        return oracle(checkpoint, observation, instruction)

    monkeypatch.setattr(predict, "predict_cost", predict_cost)
    rec = _episode(world, checkpoint, instructions="paraphrased")
    assert rec["instructions"] == "paraphrased" and rec["instruction"] != sample.instruction
    assert set(asked) == {rec["instruction"]}
    assert rec["error"] is None and rec["success"], rec["reason"]
    words = load_checkpoint(checkpoint).vocabulary.words
    unknown = [w for w in tokenise(rec["instruction"]) if w not in words]
    assert unknown  # the reworded instruction holds words outside the training instructions


def test_unet_runs_seen_and_paraphrased_instructions_only(checkpoint: Path) -> None:
    from voxposer.bench.runner import BenchConfig
    from voxposer.errors import ConfigError

    cfg = BenchConfig(tasks=(TASK,), method=UNET_MP, llm=NO_LLM, unet_checkpoint=checkpoint,
                      workers=1, instructions="paraphrased")
    assert {j.instructions for j in cfg.jobs()} == {"paraphrased"}
    with pytest.raises(ConfigError, match=r"'seen' or 'paraphrased'.*instructions='unseen'"):
        BenchConfig(tasks=(TASK,), method=UNET_MP, llm=NO_LLM, unet_checkpoint=checkpoint,
                    workers=1, instructions="unseen")


def test_a_block_is_pushed_along_the_true_cost(world, checkpoint: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    """An object task: the predicted map is the block's cost; the pushing loop follows it."""
    block = episode_sample(world, "push_to_pos", SEED)
    assert block.entity.endswith("block")
    monkeypatch.setattr(predict, "predict_cost", _oracle(block.cost))
    rec = _episode(world, checkpoint, "push_to_pos")
    assert rec["error"] is None and rec["success"], rec["reason"]


def test_a_multistep_task_stops_after_its_first_subtask(world, checkpoint: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    """drop_to_pos: the grasp (the training target) runs and lifts the block; the carry has
    no cost map, so it is not run and the record says why."""
    grasp = episode_sample(world, "drop_to_pos", SEED)
    monkeypatch.setattr(predict, "predict_cost", _oracle(grasp.cost))
    rec = _episode(world, checkpoint, "drop_to_pos")
    assert rec["error"] is None and not rec["success"]
    assert "still held" in rec["reason"]
    assert "(not run)" in rec["program_error"] and "first sub-task" in rec["program_error"]


def test_a_constant_prediction_fails(world, checkpoint: Path,
                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(predict, "predict_cost", _oracle(np.full((50, 50, 50), 1.5)))
    rec = _episode(world, checkpoint)
    assert rec["error"] is None and not rec["success"]


def test_a_trained_checkpoint_runs_and_the_record_names_it(world, checkpoint: Path) -> None:
    rec = _episode(world, checkpoint)
    assert rec["error"] is None, rec["error"]
    assert rec["method"] == UNET_MP and rec["llm"] == NO_LLM
    sha = hashlib.sha256(checkpoint.read_bytes()).hexdigest()
    assert rec["unet_checkpoint"] == {"path": str(checkpoint), "sha256": sha[:16]}
    assert rec["sim_time_s"] > 0  # the robot ran the predicted-cost plans


def test_an_object_target_is_the_lowest_cost_in_its_layer(world, checkpoint: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """Pushing: the predicted map is the object's cost; its target stays at the object's
    height even where the prediction is lower elsewhere."""
    from voxposer.unet.checkpoint import load_checkpoint

    cost = np.full((50, 50, 50), 2.0, dtype=np.float32)
    cost[10, 10, 40] = 0.0  # the global minimum, high above the table
    cost[30, 20, :] = 0.5  # the lowest cost of every layer
    monkeypatch.setattr(predict, "predict_cost", _oracle(cost))
    body = Embodiment.simulated(world)
    config = ExecutorConfig().object_planner
    planner = PredictedCostPlanner(world.grid, config, load_checkpoint(checkpoint), "push",
                                   body.perceiver.point_cloud)
    start = np.array([-0.25, 0.0, 0.03])
    plan = planner.plan(np.zeros(world.grid.shape), start, layer_z=0.03)
    coarse = plan.cost_map.grid
    assert np.array_equal(np.argwhere(plan.cost_map.target_mask)[:, :2], [[30, 20]])
    assert coarse.world_to_voxel(plan.target)[2] == coarse.world_to_voxel(start)[2]
    np.testing.assert_allclose(plan.trajectory.positions[:, 2], plan.trajectory.positions[0, 2],
                               atol=coarse.resolution[2])


def test_every_task_names_what_its_first_subtask_moves() -> None:
    """The entity and the grasp come from the reference plan's first sub-task (never its maps);
    the 13 tasks move the hand, a block or a drawer handle, and the two picks grasp."""
    for name, task in TASKS.items():
        attrs = task.sample_attributes(np.random.default_rng(0), "seen")
        first = first_subtask(task.reference(attrs), task.instruction(attrs))
        assert first.entity == "gripper" or first.entity in (
            attrs.get("obj"), *(f"{d} drawer handle" for d in ("top", "middle", "bottom")))
        assert first.grasps == (name in ("grasp_at_velocity", "drop_to_pos")), name
    drop = get_task("drop_to_pos")
    attrs = drop.sample_attributes(np.random.default_rng(0), "seen")
    then = first_subtask(drop.reference(attrs), drop.instruction(attrs)).then
    assert then[0] == "back to default pose" and then[1].startswith("move the")


def test_a_checkpoint_for_another_grid_is_refused_naming_both_shapes(tmp_path: Path) -> None:
    from voxposer.bench.runner import BenchConfig
    from voxposer.errors import ConfigError

    vocabulary = Vocabulary.build(["move to the table"])
    model = make_model(UNetConfig(base_channels=4, depth=1, embed_dim=4), vocabulary, (12, 12, 8),
                       np.random.default_rng(0))
    other = save_checkpoint(tmp_path / "small.pt", model, vocabulary, (12, 12, 8), 3.0)
    with pytest.raises(ConfigError, match=r"\(12, 12, 8\).*\(50, 50, 50\)"):
        BenchConfig(tasks=(TASK,), method=UNET_MP, llm=NO_LLM, unet_checkpoint=other, workers=1)


def test_the_cli_passes_the_checkpoint_to_the_run(checkpoint: Path) -> None:
    import voxposer.cli as cli
    from voxposer.cli import bench

    args = cli.build_parser().parse_args(["bench", "--method", UNET_MP, "--unet-checkpoint",
                                          str(checkpoint), "--tasks", TASK, "--workers", "1"])
    bench.check_args(args)  # no error: the LLM is "none" without --llm
    cfg = bench._config(args)
    assert cfg.llm == NO_LLM and cfg.unet_checkpoint == checkpoint
    assert {j.unet_checkpoint for j in cfg.jobs()} == {str(checkpoint)}
