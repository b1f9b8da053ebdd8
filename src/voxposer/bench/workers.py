"""Where episodes run: one world per worker, in a local process pool (Ray actors:
:mod:`voxposer.bench.ray_pool`).

One world per worker process (MuJoCo models and renderers are not shared), and one LLM backend
with it. ``local`` runs ``workers`` spawned processes (``workers=1``: this process); ``ray`` runs
actors on a Ray cluster (the ``ray`` extra). Both yield each finished episode's record as soon
as it is done.

A local worker process that dies (a segfault, an out-of-memory kill) yields an ``error`` record
for its episode (:class:`~voxposer.errors.WorkerCrashedError`, with the signal or exit code) and
is replaced; the run goes on. Worker processes ignore SIGINT and SIGTERM (the parent decides:
closing the stream, as an interrupted run does, kills the busy ones and stops the idle ones), and
exit on their own when the parent is gone (killed with ``kill -9``).
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import multiprocessing
import os
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Generator
from multiprocessing.connection import Connection
from multiprocessing.connection import wait as wait_for
from multiprocessing.process import BaseProcess
from typing import Any, Protocol

from voxposer.bench.config import Tolerances
from voxposer.bench.episode import EpisodeJob, EpisodeRecord, run_episode
from voxposer.bench.methods import BACKENDLESS_LLMS
from voxposer.errors import VoxPoserError, WorkerCrashedError
from voxposer.lmp.backends.config import LLMConfig

log = logging.getLogger(__name__)
#: What a pool yields: each finished episode's record (closing it stops the workers).
Records = Generator[dict[str, Any], None, None]
#: How often a worker process checks that its parent is still there [s].
PARENT_POLL_S = 0.5


class EpisodeRunner(Protocol):
    """What runs episodes in one worker process (:class:`EpisodeWorker`: a world and a backend)."""

    def run(self, job: EpisodeJob) -> dict[str, Any]: ...


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
    @property
    def perception(self) -> str: ...


# ------------------------------------------------------------------------ worker side
def worker_llm_config(llm: str, overrides: dict[str, Any]) -> LLMConfig:
    """The environment's LLMConfig with backend ``llm`` and ``overrides``; a ``cache_dir``
    override (a run's own response cache) leaves the prefix-state store where it was."""
    base = LLMConfig.from_env()
    values = dict(overrides)
    if "cache_dir" in values:
        values.setdefault("prefix_cache_dir", base.resolved_prefix_cache_dir)
    return dataclasses.replace(base, backend=llm, **values)  # type: ignore[arg-type]


class EpisodeWorker:
    """One world (and one LLM backend) per worker process, perceived with ``perception``
    (:data:`voxposer.pipeline.PERCEPTIONS`), which each record names."""

    def __init__(self, llm: str, overrides: dict[str, Any],
                 perception: str = "ground-truth") -> None:
        from voxposer.envs import TabletopWorld
        from voxposer.pipeline import use_perception

        use_perception(perception)
        self.perception = perception
        self.world = TabletopWorld()
        self.backend = None
        if llm not in BACKENDLESS_LLMS:
            from voxposer.lmp.backends import make_backend

            self.backend = make_backend(worker_llm_config(llm, overrides))
        self.tol = Tolerances()

    def run(self, job: EpisodeJob) -> dict[str, Any]:
        return {**run_episode(job, self.world, self.backend, self.tol).to_json(),
                "perception": self.perception}


def _exit_with_parent() -> None:
    """Exit this (worker) process soon after its parent is gone (killed with ``kill -9``)."""
    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_POLL_S)
        os._exit(1)

    threading.Thread(target=watch, name="parent-watch", daemon=True).start()


def _serve(conn: Connection, make_worker: Callable[[], EpisodeRunner]) -> None:
    """A worker process: build the worker, then run each job received until None (or EOF).

    Messages to the parent: ``("ready", pid)``, ``("record", dict)`` per job, or
    ``("failed", text)`` when the worker cannot be built.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent handles stop signals
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    _exit_with_parent()
    try:
        worker = make_worker()
    except Exception as exc:
        conn.send(("failed", f"{type(exc).__name__}: {exc}"))
        return
    conn.send(("ready", os.getpid()))
    while True:
        try:
            job = conn.recv()
        except EOFError:
            return
        if job is None:
            return
        try:
            record = worker.run(job)
        except Exception as exc:  # run_episode records its own failures; this is a last resort
            record = error_record(job, exc)
        conn.send(("record", record))


@dataclasses.dataclass
class _Slot:
    """One worker process, its pipe, and the job it is running (None: idle)."""

    process: BaseProcess
    conn: Connection
    job: EpisodeJob | None = None
    ready: bool = False


class LocalPool:
    """``workers`` spawned worker processes, each built by ``make_worker`` (picklable); a
    process that dies is recorded (its episode) and replaced."""

    def __init__(self, make_worker: Callable[[], EpisodeRunner], workers: int) -> None:
        self.make_worker = make_worker
        self.workers = workers
        self._context = multiprocessing.get_context("spawn")

    def _start(self) -> _Slot:
        ours, theirs = self._context.Pipe()
        process = self._context.Process(target=_serve, args=(theirs, self.make_worker),
                                        name="voxposer-bench-worker", daemon=True)
        process.start()
        theirs.close()
        return _Slot(process, ours)

    def run(self, jobs: list[EpisodeJob]) -> Records:
        """Run ``jobs``, yielding each record as it finishes (see the module docs)."""
        queue = deque(jobs)
        slots = [self._start() for _ in range(min(self.workers, len(queue)))]
        try:
            for slot in slots:
                _give(slot, queue)
            while busy := [k for k, slot in enumerate(slots) if slot.job is not None]:
                ready = set(wait_for([w for k in busy
                                      for w in (slots[k].conn, slots[k].process.sentinel)]))
                for k in busy:
                    slot = slots[k]
                    if slot.job is None or not {slot.conn, slot.process.sentinel} & ready:
                        continue
                    record = self._collect(slot, slot.job)
                    if record is None:
                        continue
                    if not slot.process.is_alive():
                        slot.conn.close()
                        slots[k] = self._start()
                    _give(slots[k], queue)
                    yield record
        finally:
            _stop(slots)

    def _collect(self, slot: _Slot, job: EpisodeJob) -> dict[str, Any] | None:
        """The record of ``job`` (``slot``'s) if it finished, or an error record if the process
        died; None when the message was only "ready".

        Raises:
            VoxPoserError: the worker could not be built, or its process died before it was.
        """
        try:
            kind, value = slot.conn.recv() if slot.conn.poll() else ("died", None)
        except (EOFError, OSError):
            kind, value = "died", None
        if kind == "ready":
            slot.ready = True
            return None
        if kind == "record":
            return value
        if kind == "failed":
            raise VoxPoserError(f"a benchmark worker process could not start: {value}")
        slot.process.join(timeout=5)
        if not slot.ready:
            raise WorkerCrashedError(f"a benchmark worker process {_how(slot.process)} while "
                                     "it was starting (building its world and model)")
        log.warning("worker process %s %s during episode %s; starting another",
                    slot.process.pid, _how(slot.process), job.key)
        return _crash_record(job, slot.process)


def _give(slot: _Slot, queue: deque[EpisodeJob]) -> None:
    """Send ``slot`` the next job, or None (stop) when there is none left."""
    slot.job = queue.popleft() if queue else None
    try:
        slot.conn.send(slot.job)
    except OSError:  # it died meanwhile: seen as a death by the next wait
        pass


def _stop(slots: list[_Slot]) -> None:
    """Stop every worker process: kill the busy ones (an interrupted run), let the idle ones
    exit."""
    for slot in slots:
        if slot.job is not None and slot.process.is_alive():
            slot.process.kill()
    for slot in slots:
        slot.process.join(timeout=5)
        if slot.process.is_alive():
            slot.process.kill()
            slot.process.join()
        slot.conn.close()


def _how(process: BaseProcess) -> str:
    """"was killed by SIGKILL" / "exited with code 1" for a dead process."""
    code = process.exitcode
    if code is not None and code < 0:
        try:
            return f"was killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"was killed by signal {-code}"
    return f"exited with code {code}"


def _crash_record(job: EpisodeJob, process: BaseProcess) -> dict[str, Any]:
    """The error record of ``job``, whose worker process died running it."""
    how = _how(process)
    err = WorkerCrashedError(f"the worker process (pid {process.pid}) {how} while running this "
                             "episode; it was replaced")
    rec = EpisodeRecord.for_job(job)
    rec.error = f"{type(err).__name__}: {err}"
    rec.reason = f"error: worker process {how}"
    return rec.to_json()


# ------------------------------------------------------------------------ pools
def run_local(cfg: ExecutorSettings, jobs: list[EpisodeJob],
              make_worker: Callable[[], EpisodeRunner] | None = None
              ) -> Records:
    """Run ``jobs`` on ``cfg.workers`` local processes (1: in this process), yielding each
    record as it finishes; ``make_worker`` builds a process's runner (default: a world and the
    backend of ``cfg``)."""
    factory = make_worker or functools.partial(EpisodeWorker, cfg.llm, cfg.llm_overrides,
                                               cfg.perception)
    if cfg.workers == 1:
        worker = factory()
        for job in jobs:
            yield worker.run(job)
        return
    yield from LocalPool(factory, cfg.workers).run(jobs)


def error_record(job: EpisodeJob, exc: BaseException) -> dict[str, Any]:
    """The record of ``job`` whose worker failed with ``exc``."""
    rec = EpisodeRecord.for_job(job)
    rec.error = f"{type(exc).__name__}: {exc}"
    rec.reason = f"error: worker failed: {exc}"
    return rec.to_json()
