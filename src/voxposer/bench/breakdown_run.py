"""``voxposer bench --breakdown``: attribute every failed episode of benchmark runs, resumably.

Each run folder's failures are re-run (:func:`voxposer.bench.breakdown.attribute`) and their
attributions appended, as each finishes, to ``<run>/breakdown.jsonl``; a second call continues
where the first stopped (attributions of another code version are kept and reported, the re-runs
go on with this one). Every failure is checked to be re-runnable before any work starts.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from voxposer.bench.breakdown import attribute, check_rerunnable, failed_records, record_key
from voxposer.bench.results import load_records, repair_torn_tail
from voxposer.errors import ConfigError

#: the attributions file in a run folder.
BREAKDOWN_FILE = "breakdown.jsonl"


@dataclass(frozen=True)
class RunBreakdown:
    """A run's episodes and the attributions of its failures.

    Attributes:
        folder: the run folder (its ``episodes.jsonl``).
        records: every episode record of the run.
        attributions: the failures attributed so far (``breakdown.jsonl`` lines).
    """

    folder: Path
    records: list[dict[str, Any]]
    attributions: list[dict[str, Any]]


def load_run(folder: Path, tasks: tuple[str, ...] | None = None) -> RunBreakdown:
    """A run folder's records (those of ``tasks`` only, when given) and attributions; a folder
    without ``episodes.jsonl`` raises ConfigError naming it."""
    results = folder / "episodes.jsonl"
    if not results.is_file():
        raise ConfigError(f"--breakdown {folder}: no episodes.jsonl there (a `voxposer bench` "
                          "output folder is needed)")
    records = [r for r in load_records(results) if tasks is None or r.get("task") in tasks]
    return RunBreakdown(folder, records, load_records(folder / BREAKDOWN_FILE))


def pending(run: RunBreakdown) -> list[dict[str, Any]]:
    """The run's failed records not attributed yet, each checked to be re-runnable."""
    done = {record_key(a) for a in run.attributions}
    todo = [r for r in failed_records(run.records) if record_key(r) not in done]
    for r in todo:
        check_rerunnable(r)
    return todo


def break_down(runs: list[RunBreakdown], world: Any,
               on_start: Callable[[int], None] | None = None,
               on_attribution: Callable[[dict[str, Any]], None] | None = None
               ) -> list[RunBreakdown]:
    """Attribute every pending failure of ``runs`` in ``world``, appending each to its run's
    ``breakdown.jsonl`` as it finishes; returns the runs with all their attributions."""
    todo = [(run, pending(run)) for run in runs]
    if on_start is not None:
        on_start(sum(len(t) for _, t in todo))
    out = []
    for run, records in todo:
        path = run.folder / BREAKDOWN_FILE
        repair_torn_tail(path)
        found = list(run.attributions)
        for rec in records:
            line = attribute(rec, world).to_json()
            with path.open("a", encoding="utf-8") as fh:
                fh.write(json.dumps(line) + "\n")
            found.append(line)
            if on_attribution is not None:
                on_attribution(line)
        out.append(RunBreakdown(run.folder, run.records, found))
    return out


__all__ = ["BREAKDOWN_FILE", "RunBreakdown", "break_down", "load_run", "pending"]
