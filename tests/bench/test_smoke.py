"""CI smoke test: one seen and one unseen episode of every task with the reference programs
(hand-written programs replace the LLM; perception, planning, control and checks are real)."""

from __future__ import annotations

import pytest

from voxposer.bench import TASKS, EpisodeJob, run_episode


@pytest.mark.parametrize("name", list(TASKS))
def test_reference_programs_succeed(world, name: str) -> None:
    for split in ("seen", "unseen"):
        record = run_episode(EpisodeJob(name, split, seed=0, max_time_s=30.0), world)
        assert record.error is None, record.error
        assert record.success, (record.instruction, record.reason, record.program_error)
        assert record.llm_calls > 0
