"""A wall-clock guard for fault tests: run a call in a thread and fail if it does not end.

The limits are generous on purpose (the machine may be busy): they catch a hang, they do not
measure speed.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TypeVar

import pytest

T = TypeVar("T")


def within(seconds: float, call: Callable[[], T]) -> T:
    """``call()``'s result, or its exception re-raised; fails the test if it runs past
    ``seconds`` [s] (the call's thread is then abandoned, as a daemon)."""
    outcome: dict[str, object] = {}

    def run() -> None:
        try:
            outcome["value"] = call()
        except BaseException as exc:  # re-raised in the test's thread below
            outcome["error"] = exc

    thread = threading.Thread(target=run, daemon=True, name="bounded-call")
    thread.start()
    thread.join(seconds)
    if thread.is_alive():
        pytest.fail(f"the call did not end within {seconds:g} s (it hangs)")
    if "error" in outcome:
        raise outcome["error"]  # type: ignore[misc]
    return outcome["value"]  # type: ignore[return-value]
