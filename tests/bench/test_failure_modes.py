"""Failure reasons map to short failure modes: numbers and attribute values dropped, program
errors by class and first words, crashes by exception class."""

from __future__ import annotations

import pytest

from voxposer.bench.failure_modes import failure_mode, normalise_reason


@pytest.mark.parametrize(("reason", "mode"), [
    ("end effector 3.2 cm outside the back side of the table", "end effector outside the place"),
    ("end effector 12 cm high over the front left corner of the table",
     "end effector high over the place"),
    ("block 4.1 cm outside the front right corner of the table", "block outside the place"),
    ("the top drawer is open 5.3 cm", "the drawer is open"),
    ("the bottom drawer is open -0.0 cm", "the drawer is open"),
    ("end effector at the right side of the table; median speed 0.52x default in the zone "
     "(outside [0.9, 1.1] for 'faster speed')",
     "end effector at the place; median speed default in the zone (outside)"),
    ("end effector at the back left corner of the table; median speed 1.00x default in the zone "
     "(outside [1.25, inf] for 'faster speed')",
     "end effector at the place; median speed default in the zone (outside)"),
    ("block at the back left corner of the table; closest 2.0 cm to the red block, which moved "
     "3.0 cm", "block at the place; closest to the block, which moved"),
])
def test_reasons_lose_numbers_and_attribute_values(reason: str, mode: str) -> None:
    assert normalise_reason(reason) == mode


def test_the_same_failure_in_different_episodes_is_one_mode() -> None:
    a = {"success": False, "reason": "block 1.2 cm outside the left side of the table"}
    b = {"success": False, "reason": "block 7.9 cm outside the back right corner of the table"}
    assert failure_mode(a) == failure_mode(b) == "block outside the place"


def test_program_errors_count_as_class_and_first_words() -> None:
    rec = {"reason": "block 3.0 cm outside the left side of the table",
           "program_error": "ExecutionFailedError: sub-task 'push the pink block to the front "
                            "right corner of the table' failed (stalled): pushing pink block "
                            "made no progress; 3.2 cm from the target"}
    assert failure_mode(rec) == "ExecutionFailedError: sub-task failed (stalled)"
    lmp = {"program_error": "LMPFailedError: composer('push the top drawer handle') failed after "
                            "2 attempt(s); last error: ExecutionFailedError: sub-task 'push' "
                            "failed (timeout): time limit 40 s reached"}
    assert failure_mode(lmp) == ("LMPFailedError: composer failed after attempt(s) — "
                                 "ExecutionFailedError: sub-task failed (timeout)")


def test_crashes_count_as_their_exception_class() -> None:
    traceback = ("Traceback (most recent call last):\n  File \"x.py\", line 1, in f\n"
                 "RuntimeError: checker bug 3")
    assert failure_mode({"error": traceback, "reason": "error: RuntimeError: checker bug 3",
                         "program_error": "SandboxError: x"}) == "crashed: RuntimeError"
    assert failure_mode({"error": "BrokenProcessPool: a worker died",
                         "reason": "error: worker failed: a worker died"}) == \
        "crashed: BrokenProcessPool"
