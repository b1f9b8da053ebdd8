"""Table 3 of the paper from the learning runs' records, and the learning-curve PNG.

Per task: zero-shot success of each program source (the recorded τ₀ runs), and for each arm
(without / with prior) the last evaluation's success and the interaction time it took, mean ±
std over seeds. A run that hit its time limit before converging shows "limit (S s)" as its
time, as the paper's "TLE".
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path
from typing import Any, Final

import numpy as np

from voxposer.errors import VoxPoserError
from voxposer.learning.zero_shot import ZeroShotTrajectory
from voxposer.plotting import pyplot, save_figure

#: The paper's Table 3: task → (zero-shot, no prior, with prior success [%], with prior time [s]).
PAPER_TABLE3: Final = {
    "door": (6.7, 58.3, 88.3, 142.3),
    "window": (3.3, 36.7, 80.0, 137.0),
    "fridge": (18.3, 70.0, 91.7, 71.0),
}


def _mean_std(values: list[float], scale: float = 1.0, digits: int = 1) -> str:
    if not values:
        return "—"
    arr = np.asarray(values) * scale
    return f"{arr.mean():.{digits}f} ± {arr.std():.{digits}f}"


def final_records(records: list[dict[str, Any]]) -> dict[tuple[str, bool], list[dict[str, Any]]]:
    """The last record of every (task, prior, seed) run, grouped by (task, prior)."""
    last: dict[tuple[str, bool, int], dict[str, Any]] = {}
    for r in records:
        key = (r["task"], bool(r["prior"]), int(r["seed"]))
        if key not in last or r["iteration"] >= last[key]["iteration"]:
            last[key] = r
    out: dict[tuple[str, bool], list[dict[str, Any]]] = defaultdict(list)
    for (task, prior, _), r in sorted(last.items()):
        out[(task, prior)].append(r)
    return out


def _arm_cells(runs: list[dict[str, Any]]) -> tuple[str, str]:
    """(success cell, time cell) of one arm over its seeds."""
    if not runs:
        return "—", "—"
    success = _mean_std([float(r.get("eval_success", 0.0)) for r in runs], 100.0)
    done = [r for r in runs if r.get("converged")]
    unfinished = [r for r in runs if not r.get("final")]
    if len(done) == len(runs):
        time_cell = _mean_std([float(r["interaction_s"]) for r in done]) + " s"
    else:
        limit = max(float(r["interaction_s"]) for r in runs)
        time_cell = f"limit ({limit:.0f} s; {len(done)}/{len(runs)} converged)"
    if unfinished:
        time_cell += f", {len(unfinished)} unfinished"
    return success + f" (n={len(runs)})", time_cell


def table3(records: list[dict[str, Any]], zero_shot: list[ZeroShotTrajectory]) -> str:
    """The Markdown table: ours beside the paper's, per task."""
    finals = final_records(records)
    sources = sorted({t.source for t in zero_shot})
    lines = ["| task | zero-shot (" + ", ".join(sources or ["none"]) + ") | no prior: success |"
             " no prior: time | with prior: success | with prior: time | paper: zero-shot / no"
             " prior / with prior (time) |",
             "|---|---|---|---|---|---|---|"]
    for task, paper in PAPER_TABLE3.items():
        zs = []
        for src in sources:
            runs = [t.success for t in zero_shot if t.task == task and t.source == src]
            zs.append(f"{100 * np.mean(runs):.0f}% ({sum(runs)}/{len(runs)})" if runs else "—")
        off = _arm_cells(finals.get((task, False), []))
        on = _arm_cells(finals.get((task, True), []))
        lines.append(f"| {task} | {' / '.join(zs) or '—'} | {off[0]} | {off[1]} | {on[0]} | "
                     f"{on[1]} | {paper[0]}% / {paper[1]}% (TLE) / {paper[2]}% "
                     f"({paper[3]} s) |")
    return "\n".join(lines) + "\n"


def write_curves(records: list[dict[str, Any]], path: Path) -> Path:
    """Evaluation success against interaction time, one panel per task, both arms.

    Raises:
        VoxPoserError: matplotlib is missing, or there is nothing to plot.
    """
    plt = pyplot("the learning-curve chart")
    runs: dict[tuple[str, bool, int], list[dict[str, Any]]] = defaultdict(list)
    for r in records:
        if "eval_success" in r:
            runs[(r["task"], bool(r["prior"]), int(r["seed"]))].append(r)
    if not runs:
        raise VoxPoserError("no evaluated iteration to plot")
    tasks = [t for t in PAPER_TABLE3 if any(k[0] == t for k in runs)]
    fig, axes = plt.subplots(1, len(tasks), figsize=(4.2 * len(tasks), 3.4), squeeze=False)
    for ax, task in zip(axes[0], tasks, strict=True):
        for (t, prior, seed), rs in sorted(runs.items()):
            if t != task:
                continue
            rs = sorted(rs, key=lambda r: r["iteration"])
            ax.plot([r["interaction_s"] for r in rs], [100 * r["eval_success"] for r in rs],
                    color="tab:blue" if prior else "tab:gray", marker="o", markersize=3,
                    label=f"{'with' if prior else 'without'} prior" if seed == min(
                        k[2] for k in runs if k[:2] == (t, prior)) else None)
        ax.set_title(task)
        ax.set_xlabel("interaction time [s, simulated]")
        ax.set_ylabel("evaluation success [%]")
        ax.set_ylim(-5, 105)
        ax.legend(loc="lower right", fontsize=8)
    return save_figure(fig, path)


__all__ = ["PAPER_TABLE3", "final_records", "table3", "write_curves"]
