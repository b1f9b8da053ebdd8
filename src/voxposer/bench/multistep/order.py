"""The check of a multi-step instruction: every step held, each after the one before.

For each step the trace gives the samples at which its condition held. Step k's *time* is the
first sample, after step k − 1's time, at which its condition held (step 1's: its first
sample). Step k is completed *in order* when step k − 1 was and

* its condition held at some sample (else: "never held", with the end state),
* it held after step k − 1's time (else: "out of order" — it held only before),
* for a ``persists`` step (an object state: a block at a place, a drawer closed) its condition
  did not hold at or before step k − 1's time (else: "out of order" — it was done first; object
  states do not come true in passing, while an end-effector pose may hold en route to another
  step and counts when it holds again after the step before),
* its constraint clause, if any, held from step k − 1's time (the episode's start for the first
  step) until the first stretch of its own condition ends (a motion that settles at a place is
  judged to its end, not only to the sample it first enters the place), and
* a ``persists`` step still holds at the end (a later step did not undo it).

The layouts make no step hold at reset. The episode succeeds when every step was completed in
order; the reason names the first step that was not. Metrics per step k (1-based):
``step{k}_held`` (1/0, held at some sample), ``step{k}_first_t`` (its first time [s from the
trace's start], −1 when never), ``step{k}_t`` (its time in the sequence, −1 when none),
``step{k}_ok`` (1/0, completed in order); plus ``steps`` and ``in_order`` (0 when some step
failed for its order).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.multistep.step import Step
from voxposer.bench.task import Verdict
from voxposer.bench.trace import Trace


class StepOutcome(NamedTuple):
    """How one step went: its first sample ever and its sample in the sequence (None: none),
    that time [s from the trace's start] (−1: none), whether it was completed in order, whether
    it failed for the order, and why it failed ("" when completed)."""

    first: int | None
    at: int | None
    time_s: float
    ok: bool
    order_failed: bool
    why: str


def first_sample(mask: np.ndarray, after: int = -1) -> int | None:
    """Index of the first True of ``mask`` (shape (T,)) after index ``after``, None if none."""
    hits = np.flatnonzero(mask[after + 1:])
    return after + 1 + int(hits[0]) if hits.size else None


def _outcome(k: int, steps: tuple[Step, ...], world: Any, trace: Trace, tol: Tolerances,
             previous: StepOutcome | None) -> StepOutcome:
    """Judge step ``k`` (0-based) given the outcome of the step before it."""
    step = steps[k]
    mask = np.asarray(step.held(world, trace, tol), dtype=bool)
    first = first_sample(mask)
    name = f"step {k + 1} ({step.label})"

    def seconds(i: int | None) -> float:
        return -1.0 if i is None else float(trace.time[i] - trace.time[0])

    if first is None:
        why = f"{name} never held: {step.describe_end(world, trace, tol)}"
        return StepOutcome(None, None, -1.0, False, False, why)
    at, start = first, 0
    if previous is not None:
        before = f"step {k} ({steps[k - 1].label})"
        if previous.at is None:
            return StepOutcome(first, None, -1.0, False, False, previous.why)
        start = previous.at
        if step.persists and first <= start:
            return StepOutcome(first, None, -1.0, False, True,
                               f"out of order: {name} first held at {seconds(first):.2f} s, "
                               f"before {before} at {previous.time_s:.2f} s")
        later = first_sample(mask, start)
        if later is None:
            return StepOutcome(first, None, -1.0, False, True,
                               f"out of order: {name} held at {seconds(first):.2f} s, before "
                               f"{before} at {previous.time_s:.2f} s, and never after it")
        at = later
        if not previous.ok:
            return StepOutcome(first, at, seconds(at), False, False, previous.why)
    stays = np.flatnonzero(~mask[at:])  # the first stretch the condition holds ends here
    end = at + int(stays[0]) if stays.size else len(mask)
    ok, why = step.constraint(world, trace, slice(start, end), tol)
    if not ok:
        return StepOutcome(first, at, seconds(at), False, False,
                           f"{name} broke its constraint: {why}")
    if step.persists and not mask[-1]:
        return StepOutcome(first, at, seconds(at), False, False,
                           f"{name} held at {seconds(at):.2f} s but no longer at the end: "
                           f"{step.describe_end(world, trace, tol)}")
    return StepOutcome(first, at, seconds(at), True, False, "")


def judge_steps(steps: tuple[Step, ...], world: Any, trace: Trace, tol: Tolerances) -> Verdict:
    """The episode's verdict from its final ``world`` and ``trace`` (see the module docs)."""
    outcomes: list[StepOutcome] = []
    for k in range(len(steps)):
        outcomes.append(_outcome(k, steps, world, trace, tol, outcomes[-1] if outcomes else None))
    metrics: dict[str, float] = {"steps": float(len(steps))}
    for k, o in enumerate(outcomes, 1):
        metrics[f"step{k}_held"] = float(o.first is not None)
        metrics[f"step{k}_first_t"] = -1.0 if o.first is None else \
            float(trace.time[o.first] - trace.time[0])
        metrics[f"step{k}_t"] = o.time_s
        metrics[f"step{k}_ok"] = float(o.ok)
    metrics["in_order"] = float(not any(o.order_failed for o in outcomes))
    times = ", ".join(f"{k}: {o.time_s:.2f} s" if o.at is not None else f"{k}: —"
                      for k, o in enumerate(outcomes, 1))
    failed = next((o for o in outcomes if not o.ok), None)
    if failed is None:
        return Verdict(True, f"all {len(steps)} steps held in order (at {times})",
                       metrics)
    return Verdict(False, f"{failed.why} (steps at {times})", metrics)
