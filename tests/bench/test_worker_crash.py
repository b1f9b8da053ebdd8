"""A benchmark worker process that dies (here: SIGKILL, as from a segfault or the out-of-memory
killer) is recorded as a crashed episode and replaced, and the run goes on; closing the stream
(an interrupted run) stops every worker process. The workers run a stand-in episode runner (no
simulator), so only the pool is tested."""

from __future__ import annotations

import functools
import json
import os
import signal
import time
from pathlib import Path
from typing import Any

import pytest

from voxposer.bench import BenchConfig, run_bench, runner, workers
from voxposer.bench.episode import EpisodeJob, EpisodeRecord
from voxposer.errors import VoxPoserError

#: the seed whose episode kills its worker process.
DEADLY_SEED = 1


class _Runner:
    """Stand-in episodes: instant successes, except that seed DEADLY_SEED kills its process."""

    def __init__(self, sleep_s: float = 0.0) -> None:
        self.sleep_s = sleep_s

    def run(self, job: EpisodeJob) -> dict[str, Any]:
        if job.seed == DEADLY_SEED:
            os.kill(os.getpid(), signal.SIGKILL)
        time.sleep(self.sleep_s)
        rec = EpisodeRecord.for_job(job)
        rec.success, rec.reason = True, f"ran in process {os.getpid()}"
        return rec.to_json()


class _Unbuildable:
    def __init__(self) -> None:
        raise RuntimeError("no GPU here")


def test_a_dead_worker_is_recorded_and_replaced(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setattr(runner, "run_local",
                        functools.partial(workers.run_local,
                                          make_worker=functools.partial(_Runner, sleep_s=1.5)))
    results = tmp_path / "episodes.jsonl"
    cfg = BenchConfig(tasks=("move_to_region",), splits=("seen",), episodes=5, workers=2)
    records = run_bench(cfg, results)
    lines = [json.loads(x) for x in results.read_text().splitlines()]
    seeds = [0, 1, 2, 3, 4]
    assert sorted(r["seed"] for r in lines) == seeds == sorted(r["seed"] for r in records)
    (dead,) = [r for r in lines if r["seed"] == DEADLY_SEED]
    assert not dead["success"] and dead["error"].startswith("WorkerCrashedError: ")
    assert "killed by SIGKILL" in dead["error"] and "replaced" in dead["error"]
    assert dead["reason"] == "error: worker process was killed by SIGKILL"
    ok = [r for r in lines if r["seed"] != DEADLY_SEED]
    assert all(r["success"] and r["error"] is None for r in ok)
    assert len({r["reason"] for r in ok}) == 2  # the replacement ran episodes too
    # --resume counts the crashed episode as done, like any crashed one
    assert run_bench(cfg, results, resume=True) == records


def test_closing_the_stream_stops_every_worker() -> None:
    jobs = [EpisodeJob("move_to_region", "seen", seed) for seed in (0, 2, 3, 4)]
    pool = workers.LocalPool(functools.partial(_Runner, sleep_s=30.0), workers=2)
    stream = pool.run(jobs)
    started = time.monotonic()
    pids: list[int] = []
    original = workers.LocalPool._start

    def spy(self: workers.LocalPool) -> Any:
        slot = original(self)
        pids.append(slot.process.pid)
        return slot

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(workers.LocalPool, "_start", spy)
        with pytest.raises(TimeoutError):
            _first_within(stream, 8.0)
        stream.close()  # what an interrupted run does
    assert len(pids) == 2 and time.monotonic() - started < 25.0
    for pid in pids:
        with pytest.raises(ProcessLookupError):
            os.kill(pid, 0)


def _first_within(stream: Any, seconds: float) -> None:
    """Wait for the stream's first record, as a run does, until an alarm interrupts it."""

    def alarm(signum: int, frame: Any) -> None:
        raise TimeoutError

    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        next(stream)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def test_a_worker_that_cannot_start_stops_the_run() -> None:
    jobs = [EpisodeJob("move_to_region", "seen", seed) for seed in (0, 2)]
    with pytest.raises(VoxPoserError, match="could not start: RuntimeError: no GPU here"):
        list(workers.LocalPool(_Unbuildable, workers=2).run(jobs))
