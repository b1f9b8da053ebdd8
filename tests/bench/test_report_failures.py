"""The report's failure modes (counted per task, videos linked only where present) and its
static vs disturbed columns, from small synthetic records (no simulation)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from voxposer.bench.config import Tolerances
from voxposer.bench.report import markdown


def _rec(seed: int, success: bool, *, disturbed: bool = False, reason: str = "",
         video: str | None = None, **extra: Any) -> dict[str, Any]:
    return {"task": "push_to_pos", "split": "seen", "seed": seed, "method": "voxposer",
            "llm": "reference", "instructions": "seen", "seed_set": "dev", "code_hash": "c0de",
            "success": success, "reason": reason, "error": None, "program_error": None,
            "timings_s": {"total": 2.0}, "llm_calls": 0, "disturbed": disturbed,
            "disturbances": [{"kind": "push_robot"}] if disturbed else [], "video": video,
            **extra}


def _section(text: str, title: str) -> str:
    return text.split(title, 1)[1].split("\n## ", 1)[0]


def test_failure_modes_are_counted_and_present_videos_linked(tmp_path: Path) -> None:
    (tmp_path / "videos").mkdir()
    (tmp_path / "videos" / "a.mp4").write_bytes(b"x")
    records = [
        _rec(0, False, reason="block 3.2 cm outside the left side of the table",
             video="videos/a.mp4"),
        _rec(1, False, reason="block 9.9 cm outside the front right corner of the table",
             video="videos/gone.mp4"),
        _rec(2, False, program_error="ExecutionFailedError: sub-task 'push' failed (stalled): x"),
        _rec(3, True),
    ]
    text = _section(markdown(records, Tolerances(), out=tmp_path), "## Failure modes")
    (row,) = [ln for ln in text.splitlines() if ln.startswith("| push_to_pos |")]
    assert "| 3 |" in row
    assert "block outside the place ×2" in row
    assert "ExecutionFailedError: sub-task failed (stalled) ×1" in row
    assert "[seen 0](videos/a.mp4)" in row and "gone.mp4" not in row


def test_static_and_disturbed_success_side_by_side() -> None:
    records = [_rec(0, True), _rec(1, True), _rec(0, False, disturbed=True, reason="x"),
               _rec(1, True, disturbed=True)]
    text = markdown(records, Tolerances())
    section = _section(text, "## Static vs disturbed")
    (row,) = [ln for ln in section.splitlines() if ln.startswith("| push the [obj] to the [pos]")]
    assert row.split("|")[3:5] == [" 100.0% (2/2) ", " 50.0% (1/2) "]
    assert "push_robot ×2" in section
    # the Table 4 tables count the static episodes only
    assert "100.0% (2/2)" in _section(text, "## VoxPoser — reference programs (no LLM)")
    assert "with disturbances" in _section(text, "## Failure modes")


def test_a_disturbed_only_run_is_labelled_and_has_no_comparison() -> None:
    text = markdown([_rec(0, True, disturbed=True)], Tolerances())
    assert "## VoxPoser — reference programs (no LLM), with disturbances" in text
    assert "## Static vs disturbed" not in text
