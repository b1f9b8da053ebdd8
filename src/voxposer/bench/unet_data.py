"""Training data of the "U-Net + MP" baseline: (observation, instruction, target cost map).

For each task and dev seed the episode is reset as the benchmark resets it (seen attributes, the
task's own instruction), the task's reference programs run through the real pipeline
(:func:`voxposer.pipeline.voxposer_runtime`), and the run is stopped at the closed-loop
executor's first plan: the target is that plan's ``cost_map.cost`` — the cost the planner
searches at the start of the episode, for the **first sub-task** and its movable (the end
effector, or the object the first ``execute`` moves), on the coarse planning grid. The
observation is the fused point cloud the planner saw, voxelised on that grid
(:func:`voxposer.unet.encoding.voxelise`). Nothing moves: an episode takes ~0.5 s.

Stored as compressed ``shard_NNNNN.npz`` files beside ``manifest.json`` (grid shape, encoding,
vocabulary, shards with counts, seeds done); a resumed run skips every (task, seed) already done.
Only dev seeds are accepted; test seeds are refused.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from voxposer.bench.protocol import DEV_SEEDS
from voxposer.errors import ConfigError, VoxPoserError
from voxposer.perception.pixel_labels import colour_cloud
from voxposer.unet.dataset import (
    MANIFEST,
    Sample,
    check_grid,
    new_manifest,
    read_manifest,
    write_shard,
)
from voxposer.unet.encoding import voxelise

log = logging.getLogger(__name__)

class _FirstPlan(VoxPoserError):
    """Raised from the executor's replan callback to stop the run at its first plan."""

    def __init__(self, plan: Any, subtask: str, entity: str) -> None:
        super().__init__("stopped at the first plan")
        self.plan, self.subtask, self.entity = plan, subtask, entity


def _first_plan(err: BaseException | None) -> _FirstPlan | None:
    """The :class:`_FirstPlan` behind ``err`` (the LMP runtime wraps it), or None."""
    for _ in range(32):  # a bounded walk down the cause chain
        if err is None or isinstance(err, _FirstPlan):
            return err
        err = err.__cause__ or err.__context__
    return None


def episode_sample(world: Any, task_name: str, seed: int) -> Sample:
    """The triple of ``task_name`` on dev seed ``seed`` in ``world`` (reset here).

    Raises:
        ConfigError: ``seed`` is not a dev seed.
        VoxPoserError: the reset or the reference programs failed before the first plan.
    """
    from voxposer.bench.methods import get_method
    from voxposer.bench.task import reset_episode
    from voxposer.bench.tasks import get_task
    from voxposer.pipeline import Embodiment, voxposer_runtime

    check_dev_seed(seed)
    task = get_task(task_name)
    setup = reset_episode(task, world, "seen", seed)
    backend = get_method("voxposer").reference_backend(task, setup.attributes)
    body = Embodiment.simulated(world)
    subtasks: list[str] = []

    def stop(result: Any, plan: Any) -> None:
        raise _FirstPlan(plan, subtasks[-1] if subtasks else "", str(result.entity))

    rng, _ = setup.rng.spawn(2)  # as Method.run: the executor's generator is the first child
    runtime, handoff = voxposer_runtime(body, backend, rng, on_replan=stop)
    handoff.on_subtask = subtasks.append
    captured = None
    try:
        runtime.run(setup.instruction)
    except VoxPoserError as err:
        captured = _first_plan(err)
        if captured is None:
            raise
    finally:
        runtime.sandbox.close()  # a process-isolated sandbox's worker
    if captured is None:
        raise VoxPoserError(f"{task_name} seed {seed}: the programs ended without planning")
    cmap = captured.plan.cost_map
    cloud = colour_cloud(world.observe(rgb=True), body.perceiver.grid)  # the views, in colour
    obs = voxelise(cloud.points, cloud.colors, cmap.grid)
    return Sample(task_name, seed, setup.instruction, captured.subtask, captured.entity,
                  obs.occupancy, obs.colour,
                  np.array(cmap.cost, dtype=np.float32),
                  float(cmap.config.affordance_weight + cmap.config.avoidance_weight))


def check_dev_seed(seed: int) -> int:
    """``seed`` if it is a dev seed; ConfigError otherwise (test seeds are never trained on)."""
    if not DEV_SEEDS.holds(int(seed)):
        raise ConfigError(f"seed {seed} is not a dev seed ({DEV_SEEDS.first}–{DEV_SEEDS.last}); "
                          "training data uses dev seeds only")
    return int(seed)


def parse_seeds(text: str, episodes: int) -> list[int]:
    """Seeds of ``--seeds``: "dev" (its first ``episodes`` seeds) or a list such as "0,5,10-19"
    (dev seeds only; ``episodes`` caps how many are taken)."""
    if text == "dev":
        return list(DEV_SEEDS.seeds(episodes))
    seeds: list[int] = []
    try:
        for part in (p.strip() for p in text.split(",") if p.strip()):
            lo, _, hi = part.partition("-")
            seeds.extend(range(int(lo), int(hi or lo) + 1))
    except ValueError as err:
        raise ConfigError(f"--seeds must be 'dev' or a list like '0,5,10-19'; got {text!r}"
                          ) from err
    if not seeds:
        raise ConfigError(f"--seeds names no seed: {text!r}")
    return [check_dev_seed(s) for s in dict.fromkeys(seeds)][:episodes]


@dataclass(frozen=True)
class DataConfig:
    """What :func:`generate` produces.

    Attributes:
        tasks: task names (see :mod:`voxposer.bench.tasks`).
        seeds: dev seeds, each run for every task.
        shard_size: samples per shard file.
    """

    tasks: tuple[str, ...]
    seeds: tuple[int, ...]
    shard_size: int = 32

    def __post_init__(self) -> None:
        from voxposer.bench.tasks import get_task

        for name in self.tasks:
            get_task(name)
        for seed in self.seeds:
            check_dev_seed(seed)
        if not self.tasks or not self.seeds:
            raise ConfigError("DataConfig needs at least one task and one seed")
        if not isinstance(self.shard_size, int) or self.shard_size < 1:
            raise ConfigError(f"DataConfig.shard_size must be an int >= 1; got "
                              f"{self.shard_size!r}")


#: called after each episode with (task, seed, what happened: "ok" or the skip reason).
EpisodeCallback = Callable[[str, int, str], None]


def generate(folder: Path, world: Any, config: DataConfig, *, resume: bool = False,
             on_episode: EpisodeCallback | None = None) -> dict[str, Any]:
    """Write the (task, seed) samples of ``config`` not yet in ``folder``; returns the manifest.

    Raises:
        ConfigError: ``folder`` holds a dataset and ``resume`` is False, or its grid differs.
    """
    folder = Path(folder)
    manifest = read_manifest(folder)
    if manifest is not None and not resume:
        raise ConfigError(f"{folder} already holds a dataset ({MANIFEST}); add --resume to add "
                          "to it, or choose another --out")
    folder.mkdir(parents=True, exist_ok=True)
    manifest = manifest or new_manifest()
    done = {(t, int(s)) for t, seeds in manifest["done"].items() for s in seeds}
    done |= {(k.rsplit("/", 1)[0], int(k.rsplit("/", 1)[1])) for k in manifest["skipped"]}
    buffer: list[Sample] = []
    try:
        for task in config.tasks:
            for seed in config.seeds:
                if (task, seed) in done:
                    continue
                try:
                    sample = episode_sample(world, task, seed)
                except VoxPoserError as err:
                    manifest["skipped"][f"{task}/{seed}"] = f"{type(err).__name__}: {err}"
                    log.warning("skipped %s seed %d: %s", task, seed, err)
                    if on_episode is not None:
                        on_episode(task, seed, f"skipped: {err}")
                    continue
                check_grid(manifest, sample)
                buffer.append(sample)
                if on_episode is not None:
                    on_episode(task, seed, "ok")
                if len(buffer) >= config.shard_size:
                    write_shard(folder, manifest, buffer)
    finally:
        write_shard(folder, manifest, buffer)
    return manifest


__all__ = ["DataConfig", "EpisodeCallback", "check_dev_seed", "episode_sample", "generate",
           "parse_seeds"]
