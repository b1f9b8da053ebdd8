"""The error breakdown's report: a table per method and a Fig. 4-style stacked bar chart.

For each (method, llm, instruction split, perception) group of the runs broken down: its
episodes, its failures, and how many failures each cause (:data:`~voxposer.bench.breakdown.
CAUSES`) took, as a share of the group's episodes (the paper's Fig. 4 plots error rates) and of
its failures; then every failure with its re-runs, so each attribution can be checked.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from voxposer.bench.breakdown import CAUSES, record_key
from voxposer.bench.report import group_label
from voxposer.errors import VoxPoserError
from voxposer.plotting import pyplot, save_figure

#: bar colours of the causes.
COLOURS = {"perception": "#4c72b0", "dynamics": "#dd8452", "specification": "#c44e52",
           "unresolved": "#aaaaaa"}

Group = tuple[str, str, str, str]


def _group(r: dict[str, Any]) -> Group:
    return (r["method"], r["llm"], r.get("instructions", "seen"),
            r.get("perception", "ground-truth"))


def _label(g: Group) -> str:
    label = group_label(g[0], g[1], g[2])
    return label if g[3] == "ground-truth" else f"{label}, {g[3]} perception"


def summarise(records: Iterable[dict[str, Any]], attributions: Iterable[dict[str, Any]]
              ) -> dict[Group, dict[str, int]]:
    """group → {"episodes", "failures", "attributed", <cause>: count} (the last record and the
    last attribution of an episode win)."""
    latest = {record_key(r): r for r in records}
    found = {record_key(a): a for a in attributions}
    out: dict[Group, dict[str, int]] = {}
    for key, r in latest.items():
        row = out.setdefault(_group(r), Counter(dict.fromkeys(
            (*CAUSES, "episodes", "failures", "attributed"), 0)))
        row["episodes"] += 1
        if not r.get("success") and r.get("llm") != "reference-blind":
            row["failures"] += 1
            if key in found:
                row["attributed"] += 1
                row[found[key]["cause"]] += 1
    return {g: dict(v) for g, v in sorted(out.items())}


def breakdown_markdown(records: list[dict[str, Any]], attributions: list[dict[str, Any]]
                       ) -> str:
    """The report (see the module docs)."""
    table = summarise(records, attributions)
    lines = ["# Error breakdown (paper Sec. 4.4, Fig. 4)", "",
             "Every failed episode re-run with its components replaced by their ground truth, "
             "cumulatively: perception (the simulator's segmentation), dynamics (the simulator "
             "as the pushing MPC's model), specification (the reference programs); a failure "
             "goes to the first replacement that makes the episode succeed "
             "(`voxposer.bench.breakdown`). Shares are of all episodes (of the failures).", "",
             "| method | episodes | failures | attributed | "
             + " | ".join(CAUSES) + " |",
             "|---|---|---|---|" + "---|" * len(CAUSES)]
    for g, row in table.items():
        n, f = row["episodes"], max(row["failures"], 1)
        cells = [f"{row[c]} ({100 * row[c] / n:.1f}% / {100 * row[c] / f:.0f}%)"
                 for c in CAUSES]
        lines.append(f"| {_label(g)} | {n} | {row['failures']} | {row['attributed']} | "
                     + " | ".join(cells) + " |")
    lines += ["", "## Every failure", "",
              "| method | task | split | seed | cause | note | re-runs (step: verdict) |",
              "|---|---|---|---|---|---|---|"]
    for a in sorted(attributions, key=lambda a: (_group(a), a["task"], a["split"], a["seed"])):
        steps = "; ".join(f"{s['step']}: {'ok' if s['success'] else s['reason'][:60]}"
                          for s in a["steps"])
        lines.append(f"| {_label(_group(a))} | {a['task']} | {a['split']} | {a['seed']} | "
                     f"{a['cause']} | {a['note']} | {steps.replace('|', '/')} |")
    return "\n".join(lines) + "\n"


def write_breakdown_chart(records: list[dict[str, Any]], attributions: list[dict[str, Any]],
                          path: Path) -> Path:
    """One stacked bar per group: each cause's share of the group's episodes [%]."""
    plt = pyplot("the error breakdown chart")
    table = summarise(records, attributions)
    if not table:
        raise VoxPoserError("no episodes to plot")
    fig, ax = plt.subplots(figsize=(2.2 + 1.9 * len(table), 4.5))
    xs = range(len(table))
    bottom = [0.0] * len(table)
    for cause in CAUSES:
        vals = [100 * row[cause] / row["episodes"] for row in table.values()]
        ax.bar(xs, vals, 0.6, bottom=bottom, label=cause, color=COLOURS[cause],
               edgecolor="black", linewidth=0.4)
        bottom = [b + v for b, v in zip(bottom, vals, strict=True)]
    ax.set_xticks(list(xs))
    ax.set_xticklabels([_label(g).replace(" — ", "\n") for g in table], fontsize=8)
    ax.set_ylabel("failed episodes [% of episodes]")
    ax.set_title("Error breakdown by component")
    ax.legend(fontsize=8)
    ax.grid(axis="y", alpha=0.3)
    return save_figure(fig, path)


def write_breakdown(records: list[dict[str, Any]], attributions: list[dict[str, Any]],
                    out: Path, *, plot: bool = True) -> Path:
    """Write ``breakdown.md`` (and ``breakdown.png``) into ``out``; returns the report's path."""
    out.mkdir(parents=True, exist_ok=True)
    report = out / "breakdown.md"
    report.write_text(breakdown_markdown(records, attributions), encoding="utf-8")
    if plot:
        write_breakdown_chart(records, attributions, out / "breakdown.png")
    return report


__all__ = ["breakdown_markdown", "summarise", "write_breakdown", "write_breakdown_chart"]
