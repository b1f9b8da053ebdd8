"""The planner's plan reviewed before it runs: the clause checklist and the post-condition
checklist over the attempts of one planner query.

The first plan with gaps (:func:`voxposer.lmp.checklist.clause_gaps`: a clause of the
instruction no sub-task carries; :func:`voxposer.lmp.unasked.unasked_gaps`: a sub-task doing
what the instruction does not ask; :func:`voxposer.lmp.intent_checklist.intent_gaps`: a
constraint of a sub-task no post-condition measures) is sent back once with the gaps listed;
after that the plan with fewer gaps runs — the correction, unless it has more than the
first (clause gaps counted before post-condition gaps: a correction that answers with one
sub-task and its post-condition has dropped the rest of the plan). When the first plan's only gaps were post-conditions, its sub-tasks run unchanged with
the correction's post-conditions grafted on (:func:`graft_conditions`): a small model asked to
restate what to measure often re-plans the motions too (adds "back to default pose").
"""

from __future__ import annotations

import ast

from voxposer.lmp.checklist import ClauseGap, checklist_message, clause_gaps, planned_subtasks
from voxposer.lmp.intent_checklist import intent_gaps, intent_message
from voxposer.lmp.unasked import KINDS as UNASKED
from voxposer.lmp.unasked import unasked_gaps, unasked_message

POST_CONDITION: str = "post-condition"


def plain_steps(code: str) -> list[tuple[str, str, list[str]]] | None:
    """A plan made only of ``composer('…')`` and ``expect(…)`` statements as (sub-task, its
    line, the expect lines after it); None for any other plan (loops, variables…)."""
    try:
        tree = ast.parse(code)
    except SyntaxError:
        return None
    steps: list[tuple[str, str, list[str]]] = []
    for stmt in tree.body:
        call = stmt.value if isinstance(stmt, ast.Expr) else None
        if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Name)):
            return None
        line = ast.get_source_segment(code, stmt) or ""
        first = call.args[0] if call.args else None
        if call.func.id == "composer" and isinstance(first, ast.Constant) \
                and isinstance(first.value, str):
            steps.append((first.value, line, []))
        elif call.func.id == "expect" and steps:
            steps[-1][2].append(line)
        else:
            return None
    return steps


def expect_calls(line: str) -> list[ast.Call]:
    """The helper calls inside one ``expect(...)`` line, e.g. ``on('gripper', 'table')``
    (none when the line does not parse as one call)."""
    try:
        call = ast.parse(line).body[0].value  # type: ignore[attr-defined]
    except (SyntaxError, IndexError, AttributeError):
        return []
    return [a for a in getattr(call, "args", []) if isinstance(a, ast.Call)
            and isinstance(a.func, ast.Name)]


def graft_conditions(plan: str, correction: str) -> str | None:
    """``plan``'s sub-tasks, in its order, each followed by the ``expect`` lines the
    ``correction`` states after the same sub-task (the plan's own where the correction has no
    such sub-task); None when either is not a plain sequence of composer/expect statements."""
    ours, theirs = plain_steps(plan), plain_steps(correction)
    if ours is None or theirs is None:
        return None
    stated: dict[str, list[str]] = {}
    for subtask, _, expects in theirs:
        stated.setdefault(subtask, expects)
    lines: list[str] = []
    for subtask, line, expects in ours:
        lines += [line, *stated.get(subtask, expects)]
    return "\n".join(lines)


def review_message(instruction: str, gaps: list[ClauseGap]) -> str:
    """The correction the planner reads for ``gaps`` of both checklists."""
    clauses = [g for g in gaps if g.kind not in (POST_CONDITION, *UNASKED)]
    parts = []
    if clauses:
        parts.append(checklist_message(instruction, clauses))
    if unasked := unasked_message([g for g in gaps if g.kind in UNASKED]):
        parts.append(unasked)
    unasked_subtasks = [f"composer({g.words!r})" for g in gaps if g.kind in UNASKED]
    post = intent_message([g for g in gaps if g.kind == POST_CONDITION
                           and not any(s in g.words for s in unasked_subtasks)])
    if post:
        parts.append(post)
    return " ".join(parts)


def _weight(gaps: list[ClauseGap]) -> tuple[int, int]:
    """How much a plan's gaps weigh when two plans are compared: what the plan leaves out or
    does unasked first, then the post-conditions it lacks (fewer is better)."""
    post = sum(g.kind == POST_CONDITION for g in gaps)
    return len(gaps) - post, post


class PlanReview:
    """Both checklists over the attempts of one planner query.

    Args:
        instruction: the planner's query.
        max_attempts: the runtime's attempts per query (the correction needs one more).
        clauses: apply the clause checklist.
        post_conditions: apply the post-condition checklist.
    """

    def __init__(self, instruction: str, max_attempts: int, *, clauses: bool = True,
                 post_conditions: bool = True) -> None:
        self.instruction = instruction
        self.max_attempts = max_attempts
        self.clauses = clauses
        self.post_conditions = post_conditions
        self._first: tuple[str, tuple[int, int], bool] | None = None

    def gaps(self, code: str) -> list[ClauseGap] | None:
        """Every gap of ``code`` (None when it does not parse: running it reports that)."""
        subtasks = planned_subtasks(code)
        if subtasks is None:
            return None
        found = (clause_gaps(self.instruction, subtasks)
                 + unasked_gaps(self.instruction, subtasks)) if self.clauses else []
        if self.post_conditions:
            found += intent_gaps(code)
        return found

    def review(self, code: str, attempt: int) -> tuple[str, str | None, list[ClauseGap]]:
        """(code to run, the correction to ask for or None, the gaps of ``code``)."""
        gaps = self.gaps(code)
        if gaps is None:
            return code, None, []
        if gaps and self._first is None and attempt < self.max_attempts:
            post_only = all(g.kind == POST_CONDITION for g in gaps)
            self._first = (code, _weight(gaps), post_only)
            return code, review_message(self.instruction, gaps), gaps
        first, self._first = self._first, None
        if first is None:
            return code, None, gaps
        plan, count, post_only = first
        if post_only and (grafted := graft_conditions(plan, code)) is not None:
            found = self.gaps(grafted) or []
            return (grafted, None, found) if _weight(found) < count else (plan, None, found)
        return (plan, None, gaps) if count < _weight(gaps) else (code, None, gaps)


__all__ = ["POST_CONDITION", "PlanReview", "graft_conditions", "plain_steps", "review_message"]
