"""The inline sandbox's memory watch: how much the process grew while generated code ran.

Size checks see one allocation at a time; many small ones (``[[0] * 10**4 for _ in
range(10**5)]``) add up unseen. While generated code runs, the tracer calls :func:`check` every
:data:`EVERY` lines; it reads the process's resident memory (``/proc/self/statm``, a few µs) and
raises a :class:`~voxposer.errors.SandboxError` once it exceeds the run's start by more than the
sandbox's byte budget. Memory that trusted callbacks take (inside ``suspend_time_limit``: a
nested LLM call loading a model) is not counted. Where ``/proc`` is missing the watch is off;
``SandboxConfig(isolation="process")`` adds an OS limit on top.
"""

from __future__ import annotations

import os
import threading
from typing import Final

from voxposer.errors import SandboxError

#: lines of generated code between two reads of the resident memory.
EVERY: Final = 256
_PAGE: Final = os.sysconf("SC_PAGE_SIZE") if hasattr(os, "sysconf") else 4096
_local = threading.local()


def resident_bytes() -> int | None:
    """The process's resident memory [bytes] (None where ``/proc`` is not available)."""
    try:
        with open("/proc/self/statm", "rb") as fh:
            return int(fh.read().split()[1]) * _PAGE
    except (OSError, ValueError, IndexError):
        return None


def _state() -> list[list[int]]:
    """Per thread: one [start bytes, budget bytes, line counter] per running execution."""
    if not hasattr(_local, "runs"):
        _local.runs = []
    return _local.runs


def start(budget_bytes: int) -> None:
    """A sandboxed execution begins: remember where memory stands."""
    now = resident_bytes()
    _state().append([now if now is not None else -1, int(budget_bytes), 0])


def stop() -> None:
    """The innermost execution ended."""
    runs = _state()
    if runs:
        runs.pop()


def check() -> None:
    """Called per traced line; every :data:`EVERY` lines compares memory with the budget."""
    runs = _state()
    if not runs:
        return
    run = runs[-1]
    run[2] += 1
    if run[0] < 0 or run[2] % EVERY:
        return
    now = resident_bytes()
    if now is not None and now - run[0] > run[1]:
        grown, run[0] = now - run[0], now  # raise once; the frames unwind
        raise SandboxError(
            f"memory limit: the generated code took {grown / 2**20:,.0f} MiB more than at its "
            f"start; the sandbox allows {run[1] / 2**20:,.0f} MiB in all")


def discount(grown_bytes: int) -> None:
    """Leave ``grown_bytes`` (what trusted code took meanwhile) out of every running budget."""
    for run in _state():
        if run[0] >= 0:
            run[0] += grown_bytes
