"""Where episodes run: one world per worker, in a local process pool or as Ray actors.

One world per worker process (MuJoCo models and renderers are not shared), and one LLM backend
with it. ``local`` runs ``workers`` spawned processes (``workers=1``: this process); ``ray`` runs
actors on a Ray cluster (the ``ray`` extra). Both yield each finished episode's record as soon
as it is done; a worker that dies yields an ``error`` record for its episode.
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import signal
from collections.abc import Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from typing import Any, Protocol

from voxposer.bench.config import Tolerances
from voxposer.bench.episode import EpisodeJob, EpisodeRecord, run_episode
from voxposer.bench.methods import REFERENCE_LLMS
from voxposer.errors import VoxPoserError
from voxposer.lmp.backends.config import LLMConfig


class ExecutorSettings(Protocol):
    """What the worker pools read of a run's configuration (a
    :class:`~voxposer.bench.runner.BenchConfig`)."""

    @property
    def workers(self) -> int: ...
    @property
    def llm(self) -> str: ...
    @property
    def llm_overrides(self) -> dict[str, Any]: ...
    @property
    def ray_address(self) -> str | None: ...


# ------------------------------------------------------------------------ worker side
def worker_llm_config(llm: str, overrides: dict[str, Any]) -> LLMConfig:
    """The environment's LLMConfig with backend ``llm`` and ``overrides``; a ``cache_dir``
    override (a run's own response cache) leaves the prefix-state store where it was."""
    base = LLMConfig.from_env()
    values = dict(overrides)
    if "cache_dir" in values:
        values.setdefault("prefix_cache_dir", base.resolved_prefix_cache_dir)
    return dataclasses.replace(base, backend=llm, **values)  # type: ignore[arg-type]


class _Worker:
    """One world (and one LLM backend) per worker process."""

    def __init__(self, llm: str, overrides: dict[str, Any]) -> None:
        from voxposer.envs import TabletopWorld

        self.world = TabletopWorld()
        self.backend = None
        if llm not in REFERENCE_LLMS:
            from voxposer.lmp.backends import make_backend

            self.backend = make_backend(worker_llm_config(llm, overrides))
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


# ------------------------------------------------------------------------ pools
def run_local(cfg: ExecutorSettings, jobs: list[EpisodeJob]) -> Iterator[dict[str, Any]]:
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
    rec = EpisodeRecord.for_job(job)
    rec.error = f"{type(exc).__name__}: {exc}"
    rec.reason = f"error: worker failed: {exc}"
    return rec.to_json()


class _RayWorker:  # wrapped by ray.remote at run time
    def __init__(self, llm: str, overrides: dict[str, Any]) -> None:
        self.worker = _Worker(llm, overrides)

    def run(self, job: EpisodeJob) -> dict[str, Any]:
        return self.worker.run(job)


def run_ray(cfg: ExecutorSettings, jobs: list[EpisodeJob]) -> Iterator[dict[str, Any]]:
    try:
        import ray
    except ImportError as exc:
        raise VoxPoserError("--pool ray needs Ray, which is not installed; install the "
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
