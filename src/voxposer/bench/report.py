"""The benchmark report: Table 4's layout (per task, SA/UA) beside the paper, Table 2-style
category aggregates, throughput, and the tolerances used — as Markdown."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from voxposer.bench.config import Tolerances
from voxposer.bench.methods import get_method
from voxposer.bench.paper import TABLE2, paper_category_means, paper_rate
from voxposer.bench.tasks import TASKS
from voxposer.envs.places import PLACES


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


def group_label(method: str, llm: str) -> str:
    """How a report names a (method, llm) group; reference programs are always labelled."""
    label = get_method(method).label
    return f"{label} — reference programs (no LLM)" if llm == "reference" else f"{label} — {llm}"


def tabulate(records: Iterable[dict[str, Any]]) -> dict[tuple[str, str], dict[tuple[str, str], Cell]]:
    """(method, llm) → (task, split) → :class:`Cell` (last record wins per episode)."""
    latest: dict[tuple[Any, ...], dict[str, Any]] = {}
    for r in records:
        latest[(r["method"], r["llm"], r["task"], r["split"], r["seed"])] = r
    out: dict[tuple[str, str], dict[tuple[str, str], Cell]] = defaultdict(lambda: defaultdict(Cell))
    for r in latest.values():
        cell = out[(r["method"], r["llm"])][(r["task"], r["split"])]
        cell.n += 1
        cell.ok += bool(r["success"])
        cell.errors += r.get("error") is not None
    return out


def _pct(v: float | None) -> str:
    return "—" if v is None else f"{v:.1f}%"


def episodes_per_hour(records: list[dict[str, Any]], method: str, llm: str) -> float:
    """Episodes per hour of one worker process for a group (3600 / mean episode wall time)."""
    times = [r["timings_s"].get("total", 0.0) for r in records
             if r["method"] == method and r["llm"] == llm]
    total = sum(times)
    return 3600.0 * len(times) / total if total > 0 else 0.0


def markdown(records: list[dict[str, Any]], tol: Tolerances, wall_rates: dict[str, float] | None
             = None) -> str:
    """The full report as Markdown."""
    lines = ["# VoxPoser simulated benchmark (paper Table 4 / Table 2)", ""]
    rows = {t.paper_row: t.category for t in TASKS.values()}
    for (method, llm), cells in sorted(tabulate(records).items()):
        column = get_method(method).paper_column
        lines += [f"## {group_label(method, llm)}", "",
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
        paper_means = paper_category_means(rows, column)
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
        rate = episodes_per_hour(records, method, llm)
        wall = (wall_rates or {}).get(f"{method}/{llm}")
        group = [r for r in records if r["method"] == method and r["llm"] == llm]
        calls = sum(int(r.get("llm_calls", 0)) for r in group)
        cached = sum(int(r.get("llm_cached_calls", 0)) for r in group)
        lines += ["", f"Throughput: {rate:.0f} episodes/hour per worker process"
                  + (f"; {wall:.0f} episodes/hour wall-clock in the last session" if wall else "")
                  + f". LLM calls: {calls}"
                  + (f", {cached} of them answered by the response cache or a recording "
                     "(a repeated identical request)" if cached else "") + ".", ""]
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
