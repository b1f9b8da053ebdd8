"""Runs many episodes in parallel worker processes and appends each record to a JSONL file.

Each finished episode is written at once, as one whole line, so an interruption (a stop signal,
``kill -9``) loses only the episodes in flight and ``resume=True`` runs only what the file does
not have yet (and only with the same code version; a torn last line is cut off first:
:mod:`voxposer.bench.results`). An interruption (KeyboardInterrupt, or a subclass the CLI raises
for SIGTERM) stops the workers before it propagates. Seeds come from a seed set
(:mod:`voxposer.bench.protocol`) or an ad-hoc first seed. ``fresh_cache`` gives the run its own,
initially empty response cache in ``<out>/cache/`` (the prefix-state store stays shared).
Worker pools (:mod:`voxposer.bench.workers`, ``pool``): ``local`` (a process pool of ``workers``
processes; ``workers=1`` runs in this process) and ``ray`` (actors on a Ray cluster; needs the
``ray`` extra). What to run is a :class:`~voxposer.bench.run_config.BenchConfig` (importable
from here too).
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Callable
from contextlib import closing
from pathlib import Path
from typing import Any

from voxposer.bench.protocol import ADHOC, TEST_SEEDS
from voxposer.bench.ray_pool import run_ray
from voxposer.bench.results import (
    append_record,
    check_resumable,
    load_records,
    record_key,
    repair_torn_tail,
)
from voxposer.bench.run_config import LLM_CHOICES, BenchConfig
from voxposer.bench.version import code_version
from voxposer.bench.workers import run_local
from voxposer.errors import ConfigError

log = logging.getLogger(__name__)

#: the response-cache folder of a ``fresh_cache`` run, inside the output folder.
FRESH_CACHE_DIR = "cache"


def fresh_cache_dir(results: Path) -> Path:
    """The response-cache folder of a ``fresh_cache`` run writing ``results``."""
    return results.parent / FRESH_CACHE_DIR


def _cache_entries(directory: Path) -> int:
    """Responses stored in the response cache of ``directory`` (0 when there is none)."""
    from voxposer.lmp.backends.cache import ResponseCache
    from voxposer.lmp.backends.factory import RESPONSE_CACHE_FILE

    path = directory / RESPONSE_CACHE_FILE
    if not path.is_file():
        return 0
    cache = ResponseCache(path)
    try:
        return len(cache)
    finally:
        cache.close()


def _with_fresh_cache(cfg: BenchConfig, results: Path, resume: bool) -> BenchConfig:
    """``cfg`` answering from ``<out>/cache/``; refuses a cache with entries unless resuming."""
    directory = fresh_cache_dir(results)
    entries = _cache_entries(directory)
    if entries and not resume:
        raise ConfigError(f"--fresh-cache: {directory} already holds {entries} cached responses; "
                          "pass --resume to continue that run, or choose another --out")
    overrides = {**cfg.llm_overrides, "cache_dir": directory}
    return dataclasses.replace(cfg, llm_overrides=overrides)


def run_bench(cfg: BenchConfig, results: Path, *, resume: bool = False,
              allow_mixed_versions: bool = False,
              on_record: Callable[[dict[str, Any]], None] | None = None,
              on_start: Callable[[int, int], None] | None = None) -> list[dict[str, Any]]:
    """Run ``cfg``'s episodes, appending each record to ``results`` as it finishes.

    Args:
        results: the JSONL file. Without ``resume`` it must not already hold records.
        resume: skip episodes ``results`` already has (crashed ones included); refused when
            its records come from another code version (see :mod:`voxposer.bench.results`).
        allow_mixed_versions: resume even a file of another code version.
        on_record: called with each new record (progress displays).
        on_start: called with (episodes to run, episodes already done).

    Returns:
        All records of ``results`` (old and new). KeyboardInterrupt (and its subclasses)
        propagates after the finished episodes are written and the workers are stopped.

    Raises:
        ConfigError: records without ``resume``; another code version without
            ``allow_mixed_versions``; a ``fresh_cache`` folder with entries without ``resume``.
    """
    old = load_records(results)
    if old and not resume:
        raise ConfigError(f"{results} already holds {len(old)} episodes; pass --resume to "
                          "continue it or choose another --out")
    check_resumable(results, old, code_version().code_hash, allow_mixed_versions)
    if cfg.fresh_cache:
        cfg = _with_fresh_cache(cfg, results, resume)
    if cfg.out_dir is None:
        cfg = dataclasses.replace(cfg, out_dir=results.parent.resolve())
    if cfg.seed_set == ADHOC and any(TEST_SEEDS.holds(s) for s in cfg.seed_list()):
        log.warning("ad-hoc seeds %s overlap the test seed set (%d-%d); use --seeds test",
                    cfg.seed_list(), TEST_SEEDS.first, TEST_SEEDS.last)
    done = {record_key(r) for r in old}
    jobs = [j for j in cfg.jobs() if j.key not in done]
    if on_start is not None:
        on_start(len(jobs), len(cfg.jobs()) - len(jobs))
    results.parent.mkdir(parents=True, exist_ok=True)
    repair_torn_tail(results)
    results.touch()
    new: list[dict[str, Any]] = []
    if not jobs:
        return old
    stream = run_ray(cfg, jobs) if cfg.pool == "ray" else run_local(cfg, jobs)
    with closing(stream), results.open("ab", buffering=0) as fh:  # closing: stop the workers
        for record in stream:
            append_record(fh, record)
            new.append(record)
            if on_record is not None:
                on_record(record)
    return old + new


__all__ = ["FRESH_CACHE_DIR", "LLM_CHOICES", "BenchConfig", "fresh_cache_dir", "load_records",
           "record_key", "run_bench"]
