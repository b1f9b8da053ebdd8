"""The benchmark report: provenance (code version, seeds, LLM calls), Table 4's layout (per
task, SA/UA) beside the paper, Table 2-style category aggregates, the reference / constraint-blind
/ model comparison, Table 2's SI/UI layout, throughput, and the tolerances used — as Markdown.

A report aggregates records of one code version only, unless ``allow_mixed``. Its tables are of
the static episodes (of the disturbed ones when there are no others); failure modes with video
links (:mod:`voxposer.bench.report_failures`) and static vs disturbed success
(:mod:`voxposer.bench.report_disturbed`) follow."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from voxposer.bench.config import Tolerances
from voxposer.bench.methods import NO_LLM, REFERENCE, REFERENCE_BLIND, REFERENCE_LLMS, get_method
from voxposer.bench.paper import TABLE2, paper_category_means, paper_rate
from voxposer.bench.protocol import INSTRUCTION_LABELS, VAGUE_RELATIONAL
from voxposer.bench.report_disturbed import disturbed_lines
from voxposer.bench.report_failures import failure_lines
from voxposer.bench.report_intent import intent_lines
from voxposer.bench.report_tables import control_lines, provenance_lines, table2_lines
from voxposer.bench.report_vague import vague_lines
from voxposer.bench.results import check_single_version, record_key
from voxposer.bench.tasks import TASKS
from voxposer.places import PLACES


@dataclass
class Cell:
    """Episodes of one (group, task, split): count, successes, crashed episodes."""

    n: int = 0
    ok: int = 0
    errors: int = 0

    @property
    def rate(self) -> float | None:
        """Success [%] (None without episodes)."""
        return 100.0 * self.ok / self.n if self.n else None

    def text(self) -> str:
        """"85.0% (17/20)" (plus crashed episodes)."""
        if not self.n:
            return "—"
        err = f", {self.errors} crashed" if self.errors else ""
        return f"{self.rate:.1f}% ({self.ok}/{self.n}{err})"


#: how reports name the groups of replayed hand-written programs, and of no LLM at all.
REFERENCE_LABELS = {REFERENCE: "reference programs (no LLM)",
                    REFERENCE_BLIND: "reference programs, constraint-blind control (no LLM)",
                    NO_LLM: "learned cost maps (no LLM)"}


def group_label(method: str, llm: str, instructions: str = "seen") -> str:
    """How a report names a (method, llm, instruction split) group; reference programs and
    their constraint-blind control are always labelled."""
    label = f"{get_method(method).label} — {REFERENCE_LABELS.get(llm, llm)}"
    return label + INSTRUCTION_LABELS.get(instructions, f", {instructions} instructions")


def tabulate(records: Iterable[dict[str, Any]]
             ) -> dict[tuple[str, str, str], dict[tuple[str, str], Cell]]:
    """(method, llm, instruction split) → (task, split) → :class:`Cell` (last record wins per
    episode)."""
    latest: dict[tuple[Any, ...], dict[str, Any]] = {}
    for r in records:
        latest[record_key(r)] = r
    out: dict[tuple[str, str, str], dict[tuple[str, str], Cell]] = defaultdict(
        lambda: defaultdict(Cell))
    for r in latest.values():
        cell = out[(r["method"], r["llm"], r.get("instructions", "seen"))][(r["task"], r["split"])]
        cell.n += 1
        cell.ok += bool(r["success"])
        cell.errors += r.get("error") is not None
    return out


def _pct(v: float | None) -> str:
    return "—" if v is None else f"{v:.1f}%"


def main_records(records: list[dict[str, Any]]) -> tuple[list[dict[str, Any]], bool]:
    """The records the main tables show — the static ones, or the disturbed ones when there
    are no static ones — and whether those are disturbed."""
    static = [r for r in records if not r.get("disturbed", False)]
    return (static, False) if static or not records else (list(records), True)


def _in_group(r: dict[str, Any], method: str, llm: str, instructions: str | None) -> bool:
    return r["method"] == method and r["llm"] == llm and (
        instructions is None or r.get("instructions", "seen") == instructions)


def episodes_per_hour(records: list[dict[str, Any]], method: str, llm: str,
                      instructions: str | None = None) -> float:
    """Episodes per hour of one worker process for a group (3600 / mean episode wall time);
    ``instructions`` None: both instruction splits."""
    times = [r["timings_s"].get("total", 0.0) for r in records
             if _in_group(r, method, llm, instructions)]
    total = sum(times)
    return 3600.0 * len(times) / total if total > 0 else 0.0


def markdown(records: list[dict[str, Any]], tol: Tolerances, wall_rates: dict[str, float] | None
             = None, allow_mixed: bool = False, out: Path | None = None) -> str:
    """The full report as Markdown.

    Args:
        out: the output folder the report is written to (failure videos present there are
            linked); None: link every video the records name.

    Raises:
        ConfigError: ``records`` come from more than one code version and not ``allow_mixed``.
    """
    check_single_version(records, allow_mixed)
    lines = ["# VoxPoser simulated benchmark (paper Table 4 / Table 2)", ""]
    lines += provenance_lines(records, allow_mixed)
    rows = {t.paper_row: t.category for t in TASKS.values()}
    everything, (records, disturbed) = records, main_records(records)
    table = tabulate(records)
    for (method, llm, instructions), cells in sorted(table.items()):
        column = get_method(method).paper_column
        lines += [f"## {group_label(method, llm, instructions)}"
                  + (", with disturbances" if disturbed else ""), "",
                  f"| Task | SA (ours) | UA (ours) | SA ({column}, paper) | UA ({column}, paper) |",
                  "|---|---|---|---|---|"]
        ours: dict[tuple[str, str], list[float]] = defaultdict(list)
        for task in TASKS.values():
            sa, ua = cells.get((task.name, "seen"), Cell()), cells.get((task.name, "unseen"), Cell())
            lines.append(f"| {task.template} | {sa.text()} | {ua.text()} | "
                         f"{_pct(paper_rate(task.paper_row, column, 'seen'))} | "
                         f"{_pct(paper_rate(task.paper_row, column, 'unseen'))} |")
            for split, cell in (("seen", sa), ("unseen", ua)):
                if cell.rate is not None:
                    ours[(task.category, split)].append(cell.rate)
        if llm != REFERENCE_BLIND:  # category means of the constrained tasks only mean nothing
            lines += _category_lines(ours, rows, column)
        rate = episodes_per_hour(records, method, llm, instructions)
        wall = (wall_rates or {}).get(f"{method}/{llm}")
        group = [r for r in records if _in_group(r, method, llm, instructions)]
        calls = sum(int(r.get("llm_calls", 0)) for r in group)
        cached = sum(int(r.get("llm_cached_calls", 0)) for r in group)
        lines += ["", f"Throughput: {rate:.0f} episodes/hour per worker process"
                  + (f"; {wall:.0f} episodes/hour wall-clock in the last session" if wall else "")
                  + f". LLM calls: {calls}"
                  + (f", {cached} of them answered by the response cache or a recording "
                     "(a repeated identical request)" if cached else "") + ".", ""]
        if instructions == VAGUE_RELATIONAL:
            lines += vague_lines(group)
    for method in sorted({g[0] for g in table}):
        lines += control_lines(table, method, get_method(method).label)
    models = sorted({(m, llm) for m, llm, _ in table if llm not in REFERENCE_LLMS})
    if models:
        lines += ["## Table 2 layout (seen/unseen instructions × attributes)", ""]
        for method, llm in models:
            lines += table2_lines(table, method, llm, group_label(method, llm))
    shaken = [r for r in everything if r.get("disturbed", False)]
    if not disturbed:
        lines += disturbed_lines(table, tabulate(shaken), shaken, group_label)
    lines += intent_lines(records, group_label)
    lines += failure_lines(everything, group_label, out)
    lines += ["## Task categories", "", "| Task | Category |", "|---|---|"]
    lines += [f"| {t.template} | {t.category} |" for t in TASKS.values()]
    lines += ["", "## Table places ([pos], [region]) — x front, y right, metres", "",
              "| Place | Kind | Target point | Success region |", "|---|---|---|---|"]
    for p in PLACES.values():
        region = (f"within {tol.corner_radius_m} m of the point" if p.kind == "corner" else
                  f"{'xy'[p.axis]} {'>=' if p.sign > 0 else '<='} {p.bound}")
        lines.append(f"| {p.name} | {p.kind} | {p.point} | {region} |")
    lines += ["", "## Tolerances", "", "| Tolerance | Value |", "|---|---|"]
    lines += [f"| {k} | {v} |" for k, v in tol.rows()]
    return "\n".join(lines) + "\n"


def _category_lines(ours: dict[tuple[str, str], list[float]], rows: Mapping[str, str],
                    column: str) -> list[str]:
    """Per-category means of our per-task rates beside the paper's Table 4 means and Table 2."""
    paper_means = paper_category_means(rows, column)
    lines: list[str] = []
    lines += ["", "| Category | SA (ours) | UA (ours) | SA (paper, mean of Table 4 rows) | "
              "UA (paper, mean of Table 4 rows) | Table 2 (paper) SI SA / SI UA / UI UA |",
              "|---|---|---|---|---|---|"]
    for category in ("Object Interactions", "Spatial Composition"):
        mine = [_pct(sum(v) / len(v)) if (v := ours.get((category, s))) else "—"
                for s in ("seen", "unseen")]
        t2 = TABLE2.get(column, {})
        t2_text = " / ".join(_pct(t2.get((k, category))) for k in ("SI SA", "SI UA", "UI UA"))
        lines.append(f"| {category} | {mine[0]} | {mine[1]} | "
                     f"{_pct(paper_means.get((category, 'seen')))} | "
                     f"{_pct(paper_means.get((category, 'unseen')))} | {t2_text} |")
    return lines
