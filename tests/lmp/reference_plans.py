"""The planner code of every task's reference programs with their post-conditions (a test
helper): the plans the checklists must never send back."""

from __future__ import annotations

from collections.abc import Iterator

from voxposer.bench.intent_reference import with_expectation
from voxposer.bench.task import episode_rng
from voxposer.bench.tasks import TASKS


def reference_plans(task: str, seeds: int = 4) -> Iterator[tuple[str, str]]:
    """(instruction, planner code) of ``task`` on both splits and the first ``seeds`` seeds."""
    for split in ("seen", "unseen"):
        for seed in range(seeds):
            attrs = TASKS[task].sample_attributes(episode_rng(task, split, seed), split)
            instruction = TASKS[task].instruction(attrs)
            code = with_expectation(TASKS[task].reference(attrs), task, attrs).code(
                "planner", instruction)
            yield instruction, code
