"""Episodes as Ray actors (``voxposer bench --pool ray``, the ``ray`` extra).

Each actor holds one :class:`~voxposer.bench.workers.EpisodeWorker` (a world and a backend) and
runs one episode at a time; records are yielded as they finish, and an actor that fails is
recorded as an error episode and replaced.
"""

from __future__ import annotations

from typing import Any

from voxposer.bench.episode import EpisodeJob
from voxposer.bench.workers import EpisodeWorker, ExecutorSettings, Records, error_record
from voxposer.errors import VoxPoserError


class _RayWorker:  # wrapped by ray.remote at run time
    def __init__(self, llm: str, overrides: dict[str, Any],
                 perception: str = "ground-truth") -> None:
        self.worker = EpisodeWorker(llm, overrides, perception)

    def run(self, job: EpisodeJob) -> dict[str, Any]:
        return self.worker.run(job)


def run_ray(cfg: ExecutorSettings, jobs: list[EpisodeJob]) -> Records:
    """Run ``jobs`` on ``cfg.workers`` actors of the Ray cluster at ``cfg.ray_address``; yield
    each record as it is done (an actor that fails is recorded and replaced)."""
    try:
        import ray
    except ImportError as exc:
        raise VoxPoserError("--pool ray needs Ray, which is not installed; install the "
                            "extra: pip install 'voxposer[ray]'") from exc
    ray.init(address=cfg.ray_address, ignore_reinit_error=True)
    actor_cls: Any = ray.remote(num_cpus=1)(_RayWorker)  # actor handles are untyped
    actors = [actor_cls.remote(cfg.llm, cfg.llm_overrides, cfg.perception)
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
                yield error_record(job, exc)
                actor = actor_cls.remote(cfg.llm, cfg.llm_overrides, cfg.perception)
            if queue:
                nxt = queue.pop(0)
                pending[actor.run.remote(nxt)] = (actor, nxt)
    finally:
        for ref in pending:
            ray.cancel(ref, force=True)
