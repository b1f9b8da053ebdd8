"""Runs many episodes in parallel worker processes and appends each record to a JSONL file.

One world per worker process (MuJoCo models and renderers are not shared). Each finished
episode is written and flushed at once, so an interruption loses only the episodes in flight and
``resume=True`` runs only what the file does not have yet. Executors: ``local`` (a process pool
of ``workers`` processes; ``workers=1`` runs in this process) and ``ray`` (actors on a Ray
cluster; needs the ``ray`` extra).
"""

from __future__ import annotations

import json
import logging
import multiprocessing
import os
import signal
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from voxposer.bench.attributes import SPLITS, check_split
from voxposer.bench.config import Tolerances
from voxposer.bench.episode import EpisodeJob, run_episode
from voxposer.bench.methods import get_method
from voxposer.bench.tasks import TASKS, get_task
from voxposer.errors import ConfigError, VoxPoserError

log = logging.getLogger(__name__)

LLM_CHOICES = ("reference", "default", "llama_cpp", "openai", "replay")


@dataclass(frozen=True)
class BenchConfig:
    """What to run.

    Attributes:
        tasks: task names (default: all 13).
        splits: "seen" and/or "unseen".
        episodes: episodes per task and split (seeds ``seed`` … ``seed + episodes − 1``).
        seed: first episode seed.
        method: "voxposer" or "llm_primitives".
        llm: "reference" (hand-written programs, labelled so) or an LLM backend kind.
        workers: parallel worker processes (default: the machine's cores).
        executor: "local" (process pool) or "ray".
        ray_address: Ray cluster address (None: ``ray.init()``'s default).
        max_time_s: simulated time limit of each ``execute`` call [s].
        llm_overrides: LLMConfig fields for the backend (model, base_url, recordings_path…).
    """

    tasks: tuple[str, ...] = tuple(TASKS)
    splits: tuple[str, ...] = SPLITS
    episodes: int = 20
    seed: int = 0
    method: str = "voxposer"
    llm: str = "reference"
    workers: int = field(default_factory=lambda: os.cpu_count() or 1)
    executor: Literal["local", "ray"] = "local"
    ray_address: str | None = None
    max_time_s: float = 40.0
    llm_overrides: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in self.tasks:
            get_task(name)
        for split in self.splits:
            check_split(split)
        get_method(self.method)
        if self.llm not in LLM_CHOICES:
            raise ConfigError(f"unknown llm {self.llm!r}; choose one of: {', '.join(LLM_CHOICES)}")
        if not isinstance(self.episodes, int) or self.episodes < 1:
            raise ConfigError(f"BenchConfig.episodes must be an int >= 1; got {self.episodes!r}")
        if not isinstance(self.workers, int) or self.workers < 1:
            raise ConfigError(f"BenchConfig.workers must be an int >= 1; got {self.workers!r}")
        if self.executor not in ("local", "ray"):
            raise ConfigError(f"unknown executor {self.executor!r}; executors are: local, ray")
        if not self.max_time_s > 0:
            raise ConfigError(f"BenchConfig.max_time_s must be > 0; got {self.max_time_s!r}")

    def jobs(self) -> list[EpisodeJob]:
        """Every episode, task-major (so partial results cover tasks evenly per seed)."""
        return [EpisodeJob(t, s, self.seed + k, self.method, self.llm, self.max_time_s)
                for k in range(self.episodes) for t in self.tasks for s in self.splits]


def load_records(path: Path) -> list[dict[str, Any]]:
    """Records of a results JSONL (a torn last line from an interruption is skipped)."""
    if not path.is_file():
        return []
    out = []
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            out.append(json.loads(line))
        except json.JSONDecodeError:
            log.warning("skipping a torn line in %s", path)
    return out


def record_key(r: dict[str, Any]) -> tuple[Any, ...]:
    """The identity of a record (matches :attr:`EpisodeJob.key`)."""
    return (r["method"], r["llm"], r["task"], r["split"], r["seed"])


# ------------------------------------------------------------------------ worker side
class _Worker:
    """One world (and one LLM backend) per worker process."""

    def __init__(self, llm: str, overrides: dict[str, Any]) -> None:
        from voxposer.envs import TabletopWorld

        self.world = TabletopWorld()
        self.backend = None
        if llm != "reference":
            import dataclasses

            from voxposer.lmp.backends import LLMConfig, make_backend

            config = dataclasses.replace(LLMConfig.from_env(), backend=llm,  # type: ignore[arg-type]
                                         **overrides)
            self.backend = make_backend(config)
        self.tol = Tolerances()

    def run(self, job: EpisodeJob) -> dict[str, Any]:
        return run_episode(job, self.world, self.backend, self.tol).to_json()


_WORKER: _Worker | None = None


def _init_process(llm: str, overrides: dict[str, Any]) -> None:
    global _WORKER
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent handles Ctrl-C
    _WORKER = _Worker(llm, overrides)


def _run_in_process(job: EpisodeJob) -> dict[str, Any]:
    if _WORKER is None:  # pragma: no cover - the initializer always runs first
        raise VoxPoserError("worker process was not initialised")
    return _WORKER.run(job)


# ------------------------------------------------------------------------ executors
def _local(cfg: BenchConfig, jobs: list[EpisodeJob]) -> Iterator[dict[str, Any]]:
    if cfg.workers == 1:
        worker = _Worker(cfg.llm, cfg.llm_overrides)
        for job in jobs:
            yield worker.run(job)
        return
    pool = ProcessPoolExecutor(max_workers=min(cfg.workers, len(jobs)),
                               mp_context=multiprocessing.get_context("spawn"),
                               initializer=_init_process, initargs=(cfg.llm, cfg.llm_overrides))
    futures: dict[Future[dict[str, Any]], EpisodeJob] = {
        pool.submit(_run_in_process, job): job for job in jobs}
    try:
        pending = set(futures)
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                try:
                    yield fut.result()
                except Exception as exc:
                    job = futures[fut]
                    yield _error_record(job, exc)
        pool.shutdown(wait=True)
    finally:
        if any(not f.done() for f in futures):  # interrupted: stop the workers now
            pool.shutdown(wait=False, cancel_futures=True)
            for proc in list(getattr(pool, "_processes", {}).values()):
                proc.terminate()


def _error_record(job: EpisodeJob, exc: BaseException) -> dict[str, Any]:
    from voxposer.bench.episode import EpisodeRecord

    rec = EpisodeRecord(job.task, job.split, job.seed, job.method, job.llm)
    rec.error = f"{type(exc).__name__}: {exc}"
    rec.reason = f"error: worker failed: {exc}"
    return rec.to_json()


class _RayWorker:  # wrapped by ray.remote at run time
    def __init__(self, llm: str, overrides: dict[str, Any]) -> None:
        self.worker = _Worker(llm, overrides)

    def run(self, job: EpisodeJob) -> dict[str, Any]:
        return self.worker.run(job)


def _ray(cfg: BenchConfig, jobs: list[EpisodeJob]) -> Iterator[dict[str, Any]]:
    try:
        import ray
    except ImportError as exc:
        raise VoxPoserError("--executor ray needs Ray, which is not installed; install the "
                            "extra: pip install 'voxposer[ray]'") from exc
    ray.init(address=cfg.ray_address, ignore_reinit_error=True)
    actor_cls: Any = ray.remote(num_cpus=1)(_RayWorker)  # actor handles are untyped
    actors = [actor_cls.remote(cfg.llm, cfg.llm_overrides)
              for _ in range(min(cfg.workers, len(jobs)))]
    queue = list(jobs)
    pending: dict[Any, tuple[Any, EpisodeJob]] = {}
    for actor in actors:
        if queue:
            job = queue.pop(0)
            pending[actor.run.remote(job)] = (actor, job)
    try:
        while pending:
            (ref,), _ = ray.wait(list(pending), num_returns=1)
            actor, job = pending.pop(ref)
            try:
                yield ray.get(ref)
            except Exception as exc:
                yield _error_record(job, exc)
                actor = actor_cls.remote(cfg.llm, cfg.llm_overrides)
            if queue:
                nxt = queue.pop(0)
                pending[actor.run.remote(nxt)] = (actor, nxt)
    finally:
        for ref in pending:
            ray.cancel(ref, force=True)


def run_bench(cfg: BenchConfig, results: Path, *, resume: bool = False,
              on_record: Callable[[dict[str, Any]], None] | None = None,
              on_start: Callable[[int, int], None] | None = None) -> list[dict[str, Any]]:
    """Run ``cfg``'s episodes, appending each record to ``results`` as it finishes.

    Args:
        results: the JSONL file. Without ``resume`` it must not already hold records.
        resume: skip episodes ``results`` already has (crashed ones included).
        on_record: called with each new record (progress displays).
        on_start: called with (episodes to run, episodes already done).

    Returns:
        All records of ``results`` (old and new). KeyboardInterrupt propagates after the
        finished episodes are written.
    """
    old = load_records(results)
    if old and not resume:
        raise ConfigError(f"{results} already holds {len(old)} episodes; pass --resume to "
                          "continue it or choose another --out")
    done = {record_key(r) for r in old}
    jobs = [j for j in cfg.jobs() if j.key not in done]
    if on_start is not None:
        on_start(len(jobs), len(cfg.jobs()) - len(jobs))
    results.parent.mkdir(parents=True, exist_ok=True)
    stream = _ray(cfg, jobs) if cfg.executor == "ray" else _local(cfg, jobs)
    new: list[dict[str, Any]] = []
    with results.open("a", encoding="utf-8") as fh:
        for record in stream if jobs else iter(()):
            fh.write(json.dumps(record) + "\n")
            fh.flush()
            new.append(record)
            if on_record is not None:
                on_record(record)
    return old + new
