"""Report section "Static vs disturbed" (the paper's Table 1 layout, in simulation).

Per (method, llm, instruction split) group holding both static and disturbed episodes
(``--disturb``, :mod:`voxposer.bench.disturb`): per task and attribute split, success without
and with disturbances side by side, and how many disturbances of each kind were applied.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Mapping
from typing import Any

from voxposer.bench.tasks import TASKS
from voxposer.control.disturbance_schedule import KINDS, DisturbanceSchedule

Group = tuple[str, str, str]  # (method, llm, instruction split)
Cells = Mapping[Group, Mapping[tuple[str, str], Any]]  # group → (task, split) → report.Cell


def disturbed_lines(static: Cells, disturbed: Cells, records: list[dict[str, Any]],
                    label: Callable[[str, str, str], str]) -> list[str]:
    """The section for every group in both ``static`` and ``disturbed`` (empty if none).

    Args:
        static, disturbed: tabulated cells (``report.tabulate``) of each kind of episode.
        records: the disturbed records (for the counts of what was applied).
        label: how the report names a group.
    """
    groups = sorted(set(static) & set(disturbed))
    if not groups:
        return []
    when = DisturbanceSchedule()
    lines = ["## Static vs disturbed (paper Table 1 layout)", "",
             "The same episodes (task, split, seed: the same start) without and with the paper's "
             "disturbances (App. A.4): a push of the robot, a displaced block and — where the "
             "entity is an object or part — reverted progress, at "
             + " / ".join(f"{p:.0%}" for p in when.progress) + " of a sub-task's progress "
             "(the baseline: at " + " / ".join(f"{t:g}" for t in when.times_s)
             + " s of simulated time).", ""]
    for group in groups:
        kinds: Counter[str] = Counter()
        for r in records:
            if (r["method"], r["llm"], r.get("instructions", "seen")) == group:
                kinds.update(d.get("kind", "?") for d in r.get("disturbances", []))
        applied = ", ".join(f"{k} ×{kinds[k]}" for k in KINDS if kinds[k]) or "none"
        lines += [f"### {label(*group)}", "", f"Disturbances applied: {applied}.", "",
                  "| Task | Split | Static | Disturbed |", "|---|---|---|---|"]
        for task in TASKS.values():
            for split in ("seen", "unseen"):
                a, b = static[group].get((task.name, split)), disturbed[group].get(
                    (task.name, split))
                if (a is None or not a.n) and (b is None or not b.n):
                    continue
                texts = ["—" if c is None else c.text() for c in (a, b)]
                lines.append(f"| {task.template} | {split} | {texts[0]} | {texts[1]} |")
        lines.append("")
    return lines


__all__ = ["disturbed_lines"]
