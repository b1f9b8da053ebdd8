"""``voxposer run`` judges itself by the plan's post-conditions too (intent checks)."""

from __future__ import annotations

import json
from pathlib import Path

from voxposer.bench.tasks import get_task
from voxposer.cli import main

INSTRUCTION = "move to the back side of the table"
ATTRS = {"region": "back side of the table"}


def run(tmp_path: Path, expect: str) -> tuple[int, dict]:
    # a test double: the task's reference programs, the plan stating ``expect``
    entries = [e for e in get_task("move_to_region").reference(ATTRS).entries()
               if e["lmp"] != "planner"]
    plan = {"lmp": "planner", "query": INSTRUCTION,
            "responses": [f"composer('move to the {ATTRS['region']}')\nexpect({expect})"]}
    recordings = tmp_path / "programs.jsonl"
    recordings.write_text("\n".join(json.dumps(e) for e in [plan, *entries]))
    out = tmp_path / "run"
    code = main(["run", INSTRUCTION, "--llm", "replay", "--recordings", str(recordings),
                 "--out", str(out), "--no-video", "--seed", "3"])
    return code, json.loads((out / "summary.json").read_text())


def test_a_false_post_condition_fails_the_run_with_it_in_the_reason(tmp_path: Path) -> None:
    code, summary = run(tmp_path, "on('gripper', 'table', 'front side')")
    assert all(s["success"] for s in summary["subtasks"])  # the target was reached ...
    assert code == 1 and summary["success"] is False  # ... but the intent was not met
    assert summary["reason"] == "post_condition_failed"
    assert "on('gripper', 'table', 'front side')" in summary["message"]
    (result,) = summary["intent"]
    assert result["held"] is False and result["subtask"] == INSTRUCTION


def test_a_true_post_condition_keeps_the_success(tmp_path: Path) -> None:
    code, summary = run(tmp_path, "on('gripper', 'table', 'back side')")
    assert code == 0 and summary["success"] is True
    assert [r["held"] for r in summary["intent"]] == [True]
