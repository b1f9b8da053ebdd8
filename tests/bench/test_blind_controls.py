"""Each constrained task tests its constraint: on a dev seed, the reference programs succeed and
the constraint-blind control (the same programs without the constraint's map) fails.

A task listed in ``NOT_BINDING`` is a measured shortfall: its blind control still succeeds
there (strict xfail, so fixing the layout turns the test red until the entry is removed).
"""

from __future__ import annotations

import json

import pytest

from voxposer.bench import TASKS, run_episode
from voxposer.bench.episode import EpisodeJob

CONSTRAINED = [name for name, task in TASKS.items() if task.constraint is not None]
#: task → why its layout does not bind yet (see the benchmark README notes).
NOT_BINDING = {
    "move_to_pos_staying_on_preposition": "'top of': from a 4 cm start the shortest way "
    "sometimes climbs over the block (seed 0) instead of passing beside it",
}


def test_the_constrained_tasks_are_the_papers_constrained_templates() -> None:
    assert set(CONSTRAINED) >= {
        "move_to_pos_min_distance", "move_to_pos_velocity_near_obj",
        "move_to_pos_velocity_in_region", "grasp_at_velocity",
        "move_to_pos_staying_on_preposition", "push_to_pos_avoid_obstacle"}
    assert "move_to_region" not in CONSTRAINED  # no constraint clause in its template


@pytest.mark.parametrize("name", [
    pytest.param(n, marks=pytest.mark.xfail(strict=True, reason=NOT_BINDING[n]))
    if n in NOT_BINDING else n for n in CONSTRAINED])
def test_the_blind_control_fails_where_the_reference_succeeds(world, name: str) -> None:
    ref = run_episode(EpisodeJob(name, "seen", 0, llm="reference"), world)
    blind = run_episode(EpisodeJob(name, "seen", 0, llm="reference-blind"), world)
    assert ref.error is None and blind.error is None, (ref.error, blind.error)
    assert ref.instruction == blind.instruction  # the same episode
    assert ref.success, ref.reason
    assert not blind.success, blind.reason
    # intent checks: the reference plan's post-conditions never contradict a passing check
    # (none are evaluated when a sub-task failed first, e.g. a push ending 2 cm short of its
    # point inside the task's region)
    assert ref.intent_verdict is not False, ref.intent
    assert ref.intent or ref.program_error, "the reference plan states its post-conditions"
    json.dumps(ref.to_json()), json.dumps(blind.to_json())  # the JSONL line can be written
