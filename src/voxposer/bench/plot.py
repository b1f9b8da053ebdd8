"""A PNG bar chart of success per task (SA / UA) for each method run, beside the paper's."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from voxposer.bench.methods import get_method
from voxposer.bench.paper import paper_rate
from voxposer.bench.report import Cell, group_label, tabulate
from voxposer.bench.tasks import TASKS
from voxposer.errors import VoxPoserError
from voxposer.plotting import pyplot, save_figure


def write_chart(records: list[dict[str, Any]], path: Path) -> Path:
    """Grouped bars: per task, our SA and UA and the paper's SA and UA; one panel per group.

    Raises:
        VoxPoserError: matplotlib is missing (it is a dependency: reinstall the package), or
            there are no episodes to plot.
    """
    plt = pyplot("the report chart")
    groups = sorted(tabulate(records).items())
    if not groups:
        raise VoxPoserError("no episodes to plot")
    names = [t.name for t in TASKS.values()]
    fig, axes = plt.subplots(len(groups), 1, figsize=(15, 4.2 * len(groups)), squeeze=False)
    width = 0.2
    for ax, ((method, llm, instructions), cells) in zip(axes[:, 0], groups, strict=True):
        column = get_method(method).paper_column
        series = [
            ("ours SA", [cells.get((n, "seen"), Cell()).rate for n in names], "#1f77b4", None),
            ("ours UA", [cells.get((n, "unseen"), Cell()).rate for n in names], "#ff7f0e", None),
            (f"paper {column} SA", [paper_rate(TASKS[n].paper_row, column, "seen") for n in names],
             "#aec7e8", "//"),
            (f"paper {column} UA",
             [paper_rate(TASKS[n].paper_row, column, "unseen") for n in names], "#ffbb78", "//"),
        ]
        for k, (label, vals, colour, hatch) in enumerate(series):
            xs = [i + (k - 1.5) * width for i in range(len(names))]
            ax.bar(xs, [v or 0.0 for v in vals], width, label=label, color=colour, hatch=hatch,
                   edgecolor="black", linewidth=0.4)
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels([n.replace("_", " ") for n in names], rotation=25, ha="right",
                           fontsize=8)
        ax.set_ylim(0, 105)
        ax.set_ylabel("success [%]")
        ax.set_title(group_label(method, llm, instructions))
        ax.legend(fontsize=8, ncol=4, loc="lower left")
        ax.grid(axis="y", alpha=0.3)
    return save_figure(fig, path)
