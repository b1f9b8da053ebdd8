"""What a benchmark run runs: :class:`BenchConfig`, checked whole when it is made.

Tasks of a suite, instruction and seed splits, the method and its LLM, the worker pool, the
perception and dynamics models; every field is validated in ``__post_init__`` (a bad value
raises :class:`~voxposer.errors.ConfigError` naming it and what is allowed), and
:meth:`BenchConfig.jobs` lists the episodes. :func:`voxposer.bench.runner.run_bench` runs them.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from voxposer.bench.attributes import SPLITS, check_split
from voxposer.bench.episode import EpisodeJob
from voxposer.bench.methods import NO_LLM, REFERENCE_BLIND, REFERENCE_LLMS, get_method
from voxposer.bench.protocol import (
    ADHOC,
    DEV_SEEDS,
    VAGUE_RELATIONAL,
    check_instructions,
    get_seed_set,
)
from voxposer.bench.push_dynamics import HEURISTIC, check_dynamics_options
from voxposer.bench.suites import (
    MULTISTEP_SUITE,
    TASKS_SUITE,
    check_suite,
    suite_names,
    suite_task,
)
from voxposer.bench.tasks import TASKS, get_task
from voxposer.bench.unet_method import check_unet_options
from voxposer.bench.videos import check_video_mode
from voxposer.errors import ConfigError
from voxposer.pipeline import check_perception

#: the ``llm`` values a run accepts.
LLM_CHOICES = ("reference", REFERENCE_BLIND, "default", "llama_cpp", "openai", "replay", NO_LLM)


@dataclass(frozen=True)
class BenchConfig:
    """What to run.

    Attributes:
        tasks: task names of ``suite`` (default: all of it — the 13 tasks, or every entry).
        splits: "seen" and/or "unseen".
        episodes: episodes per task and split.
        seeds: seed set, "dev" or "test" (the first ``episodes`` seeds of the set); None with
            ``seed`` given: ad-hoc; None without: "dev".
        seed: first seed of an ad-hoc run (seeds ``seed`` … ``seed + episodes − 1``), or None.
        method: "voxposer", "llm_primitives" or "unet_mp".
        llm: "reference" (hand-written programs, labelled so), "reference-blind" (their
            constraint-blind control; tasks without a constraint are skipped), an LLM
            backend kind, or "none" (unet_mp's only one: it runs no LLM).
        instructions: "seen", or "unseen" (each task's few-shot examples held out; LLMs only).
        workers: parallel worker processes (default: the machine's cores).
        pool: where the worker processes run: "local" (a process pool) or "ray" (actors on a
            Ray cluster).
        ray_address: Ray cluster address (None: ``ray.init()``'s default).
        max_time_s: simulated time limit of each ``execute`` call [s].
        llm_overrides: LLMConfig fields for the backend (model, base_url, recordings_path…).
        fresh_cache: answer from a response cache of this run only (``<out>/cache/``, empty at
            the start), so no response is reused from earlier runs.
        video: "none", "failures" (an MP4 per failed episode) or "all"
            (:mod:`voxposer.bench.videos`).
        disturb: run the episodes with the paper's disturbances (:mod:`voxposer.bench.disturb`);
            their records carry ``disturbed=True``, a separate identity from static ones.
        out_dir: the output folder the workers write videos to
            (:func:`~voxposer.bench.runner.run_bench` sets it to the results file's folder when
            None).
        suite: "tasks" (the 13 tasks) or "multistep" (:mod:`voxposer.bench.multistep`; seen
            instructions only, and no constraint-blind control).
        perception: how the simulated robot finds objects, one of
            :data:`voxposer.pipeline.PERCEPTIONS` ("ground-truth" segmentation, or
            "colour-depth": RGB-D pixels only); every record carries it.
        dynamics: the pushing MPC's dynamics model (:data:`~voxposer.bench.push_dynamics.
            DYNAMICS`: "heuristic", the paper's; "simulator"; "learned", from ``push_model``).
        push_model: the learned push model (``voxposer learn-push``'s ``push_model.npz``;
            required with dynamics "learned", refused otherwise).
        unet_checkpoint: the U-Net checkpoint of method "unet_mp" (required there, refused
            elsewhere: :func:`voxposer.bench.unet_method.check_unet_options`).
    """

    tasks: tuple[str, ...] = tuple(TASKS)
    splits: tuple[str, ...] = SPLITS
    episodes: int = 20
    seeds: str | None = None
    seed: int | None = None
    method: str = "voxposer"
    llm: str = "reference"
    instructions: str = "seen"
    workers: int = field(default_factory=lambda: os.cpu_count() or 1)
    pool: Literal["local", "ray"] = "local"
    ray_address: str | None = None
    max_time_s: float = 40.0
    llm_overrides: dict[str, Any] = field(default_factory=dict)
    fresh_cache: bool = False
    video: str = "none"
    disturb: bool = False
    out_dir: Path | None = None
    suite: str = TASKS_SUITE
    perception: str = "ground-truth"
    unet_checkpoint: Path | None = None
    dynamics: str = HEURISTIC
    push_model: Path | None = None

    def __post_init__(self) -> None:
        check_suite(self.suite)
        if self.suite != TASKS_SUITE and self.tasks == tuple(TASKS):  # the default: all of it
            object.__setattr__(self, "tasks", suite_names(self.suite))
        for name in self.tasks:
            suite_task(self.suite, name)
        for split in self.splits:
            check_split(split)
        get_method(self.method)
        if self.llm not in LLM_CHOICES:
            raise ConfigError(f"unknown llm {self.llm!r}; choose one of: {', '.join(LLM_CHOICES)}")
        check_dynamics_options(self.dynamics, self.push_model)
        check_unet_options(self.method, self.llm, self.unet_checkpoint, suite=self.suite,
                           instructions=self.instructions)
        if not isinstance(self.episodes, int) or self.episodes < 1:
            raise ConfigError(f"BenchConfig.episodes must be an int >= 1; got {self.episodes!r}")
        if not isinstance(self.workers, int) or self.workers < 1:
            raise ConfigError(f"BenchConfig.workers must be an int >= 1; got {self.workers!r}")
        if self.pool not in ("local", "ray"):
            raise ConfigError(f"unknown pool {self.pool!r}; pools are: local, ray")
        if not self.max_time_s > 0:
            raise ConfigError(f"BenchConfig.max_time_s must be > 0; got {self.max_time_s!r}")
        check_video_mode(self.video)
        check_perception(self.perception)
        self._check_suite_protocol()
        self._check_protocol()

    def _check_suite_protocol(self) -> None:
        """What the multi-step suite does not support: other instruction splits (its entries
        have no few-shot examples to hold out, nor paraphrases), constraint-blind controls, and
        reference programs for the LLM + Primitives baseline."""
        if self.suite != MULTISTEP_SUITE:
            return
        if self.instructions != "seen":
            raise ConfigError(f"suite {MULTISTEP_SUITE!r} runs instructions='seen' only; got "
                              f"instructions={self.instructions!r}")
        if self.llm == REFERENCE_BLIND:
            raise ConfigError(f"suite {MULTISTEP_SUITE!r} has no constraint-blind controls; "
                              f"use llm='reference' or an LLM backend, not {self.llm!r}")
        if self.llm in REFERENCE_LLMS and self.method != "voxposer":
            raise ConfigError(f"suite {MULTISTEP_SUITE!r} has reference programs for method "
                              f"'voxposer' only; got method={self.method!r} with "
                              f"llm={self.llm!r}")

    def _check_protocol(self) -> None:
        """Seeds, instruction split and the reference-blind control."""
        if self.seeds is not None and self.seed is not None:
            raise ConfigError(f"give a seed set (seeds={self.seeds!r}) or an ad-hoc first seed "
                              f"(seed={self.seed!r}), not both")
        self.seed_list()
        check_instructions(self.instructions)
        if self.instructions == "unseen" and self.llm in REFERENCE_LLMS:
            raise ConfigError(f"instructions='unseen' holds few-shot examples out of the LLM's "
                              f"prompts; llm={self.llm!r} replays hand-written programs and "
                              "has no prompts. Use instructions='seen', or an LLM backend")
        if self.instructions in ("paraphrased", VAGUE_RELATIONAL) and self.llm in REFERENCE_LLMS:
            raise ConfigError(f"instructions={self.instructions!r} rewords each task's instruction; "
                              f"llm={self.llm!r} replays programs written for the templates. "
                              "Use instructions='seen', or an LLM backend")
        if self.instructions == "unseen":
            from voxposer.lmp.prompt import check_fold

            for task in self.tasks:  # a fold that would empty some prompt stops the run here
                check_fold(task)
        if self.llm == REFERENCE_BLIND:
            if self.method != "voxposer":
                raise ConfigError(f"llm={REFERENCE_BLIND!r} (constraint-blind controls) exists "
                                  f"for method 'voxposer' only; got method={self.method!r}")
            if len(self.skipped_tasks) == len(self.tasks):
                constrained = [n for n, t in TASKS.items() if t.constraint is not None]
                raise ConfigError(f"none of the tasks {', '.join(self.tasks)} carries a "
                                  f"constraint, so llm={REFERENCE_BLIND!r} has nothing to run; "
                                  f"tasks with a constraint: {', '.join(constrained) or 'none'}")

    @property
    def seed_set(self) -> str:
        """The seed-set label of the run: "dev", "test" or "adhoc"."""
        if self.seeds is None:
            return ADHOC if self.seed is not None else DEV_SEEDS.name
        return self.seeds

    def seed_list(self) -> range:
        """The episode seeds (each task and split runs every one)."""
        if self.seed_set == ADHOC:
            first = int(self.seed or 0)
            if first < 0:
                raise ConfigError(f"BenchConfig.seed must be >= 0; got {first}")
            return range(first, first + self.episodes)
        return get_seed_set(self.seed_set).seeds(self.episodes)

    @property
    def skipped_tasks(self) -> tuple[str, ...]:
        """Tasks of ``tasks`` that are not run: under "reference-blind", those without a
        constraint (they have no constraint-blind control)."""
        if self.llm != REFERENCE_BLIND:
            return ()
        return tuple(t for t in self.tasks if get_task(t).constraint is None)

    def jobs(self) -> list[EpisodeJob]:
        """Every episode, task-major (so partial results cover tasks evenly per seed)."""
        tasks = [t for t in self.tasks if t not in self.skipped_tasks]
        out = None if self.out_dir is None else str(self.out_dir)
        return [EpisodeJob(t, s, seed, self.method, self.llm, self.max_time_s,
                           self.instructions, self.seed_set, self.disturb, self.video, out,
                           suite=self.suite, unet_checkpoint=None if self.unet_checkpoint
                           is None else str(self.unet_checkpoint), dynamics=self.dynamics,
                           push_model=None if self.push_model is None else str(self.push_model))
                for seed in self.seed_list() for t in tasks for s in self.splits]


__all__ = ["LLM_CHOICES", "BenchConfig"]
