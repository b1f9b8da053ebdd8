"""The report's intent-check section: the run's own verdict beside the task's check.

Every VoxPoser episode records the post-conditions its plan stated (``intent``) and the run's
verdict from them (``intent_verdict``: every evaluated post-condition held and no sub-task
failed; None when the plan stated none). What the run *claims* is that verdict, or, with no
post-condition, "no sub-task failed". Per group the section gives how often the plan stated
one, how often the claim agrees with the task's checker, and the false successes (the run
claims success, the checker says failure) — the issue's targets are ≥ 90% and ≤ 5%.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable
from typing import Any, NamedTuple


class IntentAgreement(NamedTuple):
    """Counts over a group's episodes."""

    n: int
    stated: int
    agree: int
    false_success: int
    false_failure: int

    @property
    def agreement(self) -> float:
        """Episodes whose claim matches the checker [%]."""
        return 100.0 * self.agree / self.n if self.n else 0.0

    @property
    def false_success_rate(self) -> float:
        """Episodes the run calls a success and the checker a failure [%]."""
        return 100.0 * self.false_success / self.n if self.n else 0.0


def claimed_success(record: dict[str, Any]) -> bool:
    """What the run says of itself: its intent verdict, or (none stated) no failed sub-task."""
    verdict = record.get("intent_verdict")
    if verdict is not None:
        return bool(verdict)
    return not record.get("program_error") and not record.get("error")


def agreement(records: list[dict[str, Any]]) -> IntentAgreement:
    """:class:`IntentAgreement` of ``records`` (crashed episodes left out)."""
    rows = [r for r in records if not r.get("error")]
    claims = [(claimed_success(r), bool(r.get("success"))) for r in rows]
    return IntentAgreement(
        n=len(rows),
        stated=sum(r.get("intent_verdict") is not None for r in rows),
        agree=sum(c == s for c, s in claims),
        false_success=sum(c and not s for c, s in claims),
        false_failure=sum(s and not c for c, s in claims))


def intent_lines(records: list[dict[str, Any]],
                 label: Callable[[str, str, str], str]) -> list[str]:
    """The Markdown section over VoxPoser's groups (empty when no record has the fields)."""
    groups: dict[tuple[str, str, str], list[dict[str, Any]]] = defaultdict(list)
    for r in records:
        if r.get("method") == "voxposer" and "intent_verdict" in r:
            groups[(r["method"], r["llm"], r.get("instructions", "seen"))].append(r)
    if not groups:
        return []
    lines = ["## Intent checks: the run's own verdict beside the task's check", "",
             "| Group | Episodes | Post-condition stated | Agreement | False success | "
             "False failure |", "|---|---|---|---|---|---|"]
    for key, rows in sorted(groups.items()):
        a = agreement(rows)
        lines.append(f"| {label(*key)} | {a.n} | {a.stated} | {a.agreement:.1f}% | "
                     f"{a.false_success_rate:.1f}% ({a.false_success}) | {a.false_failure} |")
    return [*lines, ""]
