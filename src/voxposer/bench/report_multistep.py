"""The report of the multi-step suite: per entry, how often every step was done in order, per
step how often it was, and the failures' reasons — as Markdown.

Per group (method, LLM): a table of entries (fully completed, then each step's rate of
"completed in order", from the records' ``step{k}_ok`` metrics), the overall fully-completed
fraction and the per-step-position rates, then each failed episode's reason. The report ends
with one ``key=value`` line (``fully_completed=… episodes=… entries=…``) over every group, for
scripts.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Any

from voxposer.bench.multistep import ENTRIES
from voxposer.bench.report import REFERENCE_LABELS
from voxposer.bench.report_tables import provenance_lines
from voxposer.bench.results import check_single_version, record_key
from voxposer.bench.suites import MULTISTEP_SUITE

#: at most this many failed episodes are listed per group.
MAX_FAILURES = 30


def _rate(ok: int, n: int) -> str:
    return f"{100.0 * ok / n:.1f}% ({ok}/{n})" if n else "—"


def _latest(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The last record of each episode identity."""
    latest: dict[tuple[Any, ...], dict[str, Any]] = {}
    for r in records:
        latest[record_key(r)] = r
    return list(latest.values())


def step_ok(record: dict[str, Any], k: int) -> bool | None:
    """Whether step ``k`` (1-based) of ``record`` was completed in order (None: the entry has
    no such step, or the episode crashed before its check)."""
    value = record.get("metrics", {}).get(f"step{k}_ok")
    return None if value is None else bool(value)


def _group_lines(label: str, group: list[dict[str, Any]]) -> list[str]:
    """The entry table, the totals and the failures of one (method, llm) group."""
    lines = [f"## {label}", "", "| Entry | Instruction | Fully completed | Step 1 | Step 2 | "
             "Step 3 |", "|---|---|---|---|---|---|"]
    by_entry: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for r in group:
        by_entry[r["task"]].append(r)
    per_step: dict[int, list[int]] = defaultdict(lambda: [0, 0])
    names = [n for n in ENTRIES if n in by_entry] + sorted(set(by_entry) - set(ENTRIES))
    for name in names:
        rs = by_entry[name]
        template = ENTRIES[name].template if name in ENTRIES else "(unknown entry)"
        cells = []
        for k in (1, 2, 3):
            flags = [f for f in (step_ok(r, k) for r in rs) if f is not None]
            cells.append(_rate(sum(flags), len(flags)))
            per_step[k][0] += sum(flags)
            per_step[k][1] += len(flags)
        ok = sum(bool(r["success"]) for r in rs)
        lines.append(f"| {name} | {template} | {_rate(ok, len(rs))} | {' | '.join(cells)} |")
    done = sum(bool(r["success"]) for r in group)
    steps = ", ".join(f"step {k} {_rate(*per_step[k])}" for k in (1, 2, 3) if per_step[k][1])
    crashed = sum(r.get("error") is not None for r in group)
    lines += ["", f"Fully completed (every step, in order): {_rate(done, len(group))}"
              + (f", {crashed} crashed" if crashed else "") + f". Per step: {steps}.", ""]
    failed = [r for r in group if not r["success"]]
    if failed:
        lines += ["Failures (the first step that failed):", ""]
        for r in sorted(failed, key=lambda r: (r["task"], r["split"], r["seed"]))[:MAX_FAILURES]:
            lines.append(f"- {r['task']} ({r['split']}, seed {r['seed']}): {r['reason']}")
        if len(failed) > MAX_FAILURES:
            lines.append(f"- … and {len(failed) - MAX_FAILURES} more")
        lines.append("")
    return lines


def multistep_markdown(records: list[dict[str, Any]], allow_mixed: bool = False) -> str:
    """The multi-step report of the ``multistep`` records among ``records`` (Markdown).

    Raises:
        ConfigError: the records come from more than one code version and not ``allow_mixed``.
    """
    check_single_version(records, allow_mixed)
    records = _latest([r for r in records if r.get("suite") == MULTISTEP_SUITE])
    lines = ["# VoxPoser multi-step instruction suite", ""]
    lines += provenance_lines(records, allow_mixed)
    groups: dict[tuple[str, str], list[dict[str, Any]]] = defaultdict(list)
    for r in records:
        groups[(r["method"], r["llm"])].append(r)
    for (method, llm), group in sorted(groups.items()):
        lines += _group_lines(f"{method} — {REFERENCE_LABELS.get(llm, llm)}", group)
    done = sum(bool(r["success"]) for r in records)
    fraction = done / len(records) if records else 0.0
    lines.append(f"fully_completed={fraction:.3f} episodes={len(records)} "
                 f"entries={len({r['task'] for r in records})}")
    return "\n".join(lines) + "\n"
