"""Report section "Failure modes": per group and task, the most common failure modes with counts
(:mod:`voxposer.bench.failure_modes`) and links to the failed episodes' videos.

Links are relative to the report, which lies in the output folder beside ``videos/``; with the
output folder given, only videos present there are linked.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Callable
from pathlib import Path
from typing import Any, Final

from voxposer.bench.failure_modes import failure_mode
from voxposer.bench.results import record_key
from voxposer.bench.tasks import TASKS

#: failure modes listed per task, and video links per task.
TOP_MODES: Final = 3
MAX_LINKS: Final = 6

#: (method, llm, instruction split, disturbed)
FailureGroup = tuple[str, str, str, bool]


def _latest(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The last record of each episode identity."""
    out: dict[tuple[Any, ...], dict[str, Any]] = {}
    for r in records:
        out[record_key(r)] = r
    return list(out.values())


def _links(failed: list[dict[str, Any]], out: Path | None) -> str:
    """Markdown links to the videos of ``failed`` that exist (relative to the report)."""
    videos = [r for r in failed if r.get("video") and (out is None or (out / r["video"]).is_file())]
    links = [f"[{r['split']} {r['seed']}]({r['video']})" for r in videos[:MAX_LINKS]]
    more = len(videos) - len(links)
    return (", ".join(links) + (f", … {more} more" if more else "")) or "—"


def failure_lines(records: list[dict[str, Any]], label: Callable[[str, str, str], str],
                  out: Path | None = None) -> list[str]:
    """The "Failure modes" section (empty without failures).

    Args:
        label: how the report names a (method, llm, instruction split) group.
        out: the output folder (None: link every video a record names).
    """
    failed: dict[FailureGroup, dict[str, list[dict[str, Any]]]] = defaultdict(
        lambda: defaultdict(list))
    for r in _latest(records):
        if not r["success"]:
            group = (r["method"], r["llm"], r.get("instructions", "seen"),
                     bool(r.get("disturbed", False)))
            failed[group][r["task"]].append(r)
    if not failed:
        return []
    lines = ["## Failure modes", "",
             "Per task, the most common failure modes (reasons with numbers and attribute values "
             "dropped; program errors by class and first words; crashes by exception class) and "
             "the videos of failed episodes (`--video failures|all`).", ""]
    for group, tasks in sorted(failed.items()):
        method, llm, instructions, disturbed = group
        lines += [f"### {label(method, llm, instructions)}"
                  + (", with disturbances" if disturbed else ""), "",
                  "| Task | Failed | Most common failure modes | Videos |", "|---|---|---|---|"]
        for name in [t for t in TASKS if t in tasks] + sorted(set(tasks) - set(TASKS)):
            rs = sorted(tasks[name], key=lambda r: (r["split"], r["seed"]))
            modes = Counter(failure_mode(r) for r in rs).most_common(TOP_MODES)
            text = "; ".join(f"{m.replace('|', '/')} ×{n}" for m, n in modes)
            lines.append(f"| {name} | {len(rs)} | {text} | {_links(rs, out)} |")
        lines.append("")
    return lines


__all__ = ["MAX_LINKS", "TOP_MODES", "failure_lines"]
