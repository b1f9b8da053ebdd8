"""Report sections beyond Table 4: provenance, the constraint-blind comparison, Table 2's layout.

* :func:`provenance_lines` — code version(s) with commit/dirty, seed ranges, LLM call totals.
* :func:`control_lines` — per task and split: reference programs vs their constraint-blind
  control vs the models. A layout tests its constraint only if the blind control fails there;
  a blind cell above :data:`BLIND_FLAG_PCT` is flagged.
* :func:`table2_lines` — per (method, LLM): categories × SI SA / SI UA / UI UA beside the paper.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Mapping
from typing import Any, Final

from voxposer.bench.methods import NO_LLM, REFERENCE, REFERENCE_BLIND, REFERENCE_LLMS, get_method
from voxposer.bench.paper import TABLE2
from voxposer.bench.protocol import ADHOC, INSTRUCTION_LABELS, SEED_SETS
from voxposer.bench.results import code_versions
from voxposer.bench.tasks import TASKS

#: a constraint-blind control succeeding more often than this [%] does not test its constraint.
BLIND_FLAG_PCT: Final = 10.0
BLIND_FLAG: Final = "⚠ does not test its constraint"
#: Table 2's columns: label → (instruction split, attribute split).
TABLE2_COLUMNS: Final = {"SI SA": ("seen", "seen"), "SI UA": ("seen", "unseen"),
                         "UI UA": ("unseen", "unseen")}
CATEGORIES: Final = ("Object Interactions", "Spatial Composition")
#: the paper's Table 2 columns listed beside ours.
PAPER_COLUMNS: Final = ("VoxPoser", "LLM + Prim.")

Group = tuple[str, str, str]  # (method, llm, instruction split)
Cells = Mapping[Group, Mapping[tuple[str, str], Any]]  # group → (task, split) → report.Cell


def _pct(v: float | None) -> str:
    return "—" if v is None else f"{v:.1f}%"


def provenance_lines(records: list[dict[str, Any]], mixed_allowed: bool) -> list[str]:
    """Code versions, seed ranges and LLM-call totals over every record (Markdown lines)."""
    if not records:
        return ["No episodes recorded.", ""]
    versions = code_versions(records)
    title = "Code version" if len(versions) == 1 else (
        "Code versions (MIXED" + (", allowed by --allow-mixed-versions)" if mixed_allowed
                                  else ")"))
    lines = [f"**{title}** (content hash of the package source; the identity compared):", ""]
    for code, v in sorted(versions.items()):
        git = (f"commit {', '.join(c[:10] for c in v['commits'])}" if v["commits"]
               else "not a git checkout")
        dirty = ", uncommitted changes under src/" if v["dirty"] else ""
        prompts = ", ".join(v["prompts"]) or "unknown"
        lines.append(f"- `{code}` — {git}{dirty}; prompts `{prompts}`; {v['episodes']} episodes")
    seeds: dict[str, set[int]] = defaultdict(set)
    for r in records:
        seeds[str(r.get("seed_set") or ADHOC)].add(int(r["seed"]))
    lines += ["", "**Seeds**: " + "; ".join(
        f"{name}{_set_range(name)} seeds {min(s)}–{max(s)} ({len(s)} distinct)"
        for name, s in sorted(seeds.items())) + ".", ""]
    lines += [_call_totals(records), ""]
    return lines


def _set_range(name: str) -> str:
    s = SEED_SETS.get(name)
    return f" (set {s.first}–{s.last}):" if s else ":"


def _call_totals(records: list[dict[str, Any]]) -> str:
    """One sentence: LLM calls and cached calls of model episodes, replays of reference ones."""
    model = [r for r in records if r["llm"] not in (*REFERENCE_LLMS, NO_LLM)]
    replay = [r for r in records if r["llm"] in REFERENCE_LLMS]
    learned = [r for r in records if r["llm"] == NO_LLM]
    calls = sum(int(r.get("llm_calls", 0)) for r in model)
    cached = sum(int(r.get("llm_cached_calls", 0)) for r in model)
    parts = []
    if model:
        parts.append(f"**LLM calls**: {calls} over {len(model)} model episodes, {cached} of "
                     "them answered by the response cache or a recording (no model run)")
    if replay:
        replays = sum(int(r.get("llm_calls", 0)) for r in replay)
        parts.append(f"**reference-program replays** (no LLM): {replays} over {len(replay)} "
                     "episodes")
    if learned:
        parts.append(f"**learned cost maps** (U-Net + MP, no LLM): {len(learned)} episodes")
    return ("; ".join(parts) or "No episodes") + "."


def _column_name(llm: str, instructions: str) -> str:
    name = {REFERENCE: "reference", REFERENCE_BLIND: "blind"}.get(llm, f"model: {llm}")
    return name + INSTRUCTION_LABELS.get(instructions, f", {instructions} instructions")


def control_lines(cells: Cells, method: str, method_label: str) -> list[str]:
    """The reference / blind / model table of ``method`` (empty when it has one group only)."""
    order = {REFERENCE: 0, REFERENCE_BLIND: 1}
    groups = sorted((g for g in cells if g[0] == method),
                    key=lambda g: (order.get(g[1], 2), g[1], g[2]))
    if len(groups) < 2 and not any(g[1] == REFERENCE_BLIND for g in groups):
        return []
    lines = [f"## {method_label}: reference programs vs constraint-blind control vs models", "",
             "A task tests its constraint only where the blind control (the reference programs "
             "minus the constraint's map) fails; a blind cell above "
             f"{BLIND_FLAG_PCT:.0f}% success is flagged.", "",
             "| Task | Split | Constraint | " + " | ".join(_column_name(g[1], g[2]) for g in groups)
             + " |", "|---|---|---|" + "---|" * len(groups)]
    for task in TASKS.values():
        for split in ("seen", "unseen"):
            row = [cells[g].get((task.name, split)) for g in groups]
            if not any(c is not None and c.n for c in row):
                continue
            texts = []
            for g, c in zip(groups, row, strict=True):
                text = "—" if c is None else c.text()
                if g[1] == REFERENCE_BLIND and c is not None and (c.rate or 0.0) > BLIND_FLAG_PCT:
                    text += f" {BLIND_FLAG}"
                texts.append(text)
            lines.append(f"| {task.name} | {split} | {task.constraint or '—'} | "
                         + " | ".join(texts) + " |")
    return [*lines, ""]


def _category_rate(cells: Mapping[tuple[str, str], Any], category: str,
                   split: str) -> tuple[float | None, int]:
    """(mean over the category's tasks of the success rate [%], episodes)."""
    rates, n = [], 0
    for task in TASKS.values():
        cell = cells.get((task.name, split))
        if task.category == category and cell is not None and cell.rate is not None:
            rates.append(cell.rate)
            n += cell.n
    return (sum(rates) / len(rates) if rates else None), n


def table2_lines(cells: Cells, method: str, llm: str, label: str) -> list[str]:
    """Table 2's layout for one (method, llm): ours (mean of per-task success [%] over the
    category, episodes in brackets) beside the paper's VoxPoser and LLM + Prim. (and the
    method's own column when it is another: U-Net + MP)."""
    own = get_method(method).paper_column
    columns = PAPER_COLUMNS if own in PAPER_COLUMNS else (*PAPER_COLUMNS, own)
    head = " | ".join(f"{c} (ours)" for c in TABLE2_COLUMNS)
    paper = " | ".join(f"{c} ({col}, paper)" for col in columns for c in TABLE2_COLUMNS)
    lines = [f"### Table 2 layout: {label}", "",
             "SI/UI: seen/unseen instructions (unseen: the task's few-shot examples held out of "
             "every prompt); SA/UA: seen/unseen attributes.", "",
             f"| Category | {head} | {paper} |",
             "|---|" + "---|" * (len(TABLE2_COLUMNS) * (1 + len(columns)))]
    for category in CATEGORIES:
        ours = []
        for instructions, split in TABLE2_COLUMNS.values():
            rate, n = _category_rate(cells.get((method, llm, instructions), {}), category, split)
            ours.append("—" if rate is None else f"{rate:.1f}% ({n} ep)")
        theirs = [_pct(TABLE2[col].get((c, category))) for col in columns
                  for c in TABLE2_COLUMNS]
        lines.append(f"| {category} | " + " | ".join(ours + theirs) + " |")
    return [*lines, ""]
