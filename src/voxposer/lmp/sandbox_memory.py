"""The inline sandbox's memory watch: how much the process grew while generated code ran.

Size checks see one allocation at a time; many small ones (``[[0] * 10**4 for _ in
range(10**5)]``) add up unseen. While generated code runs, the tracer calls :func:`check` every
:data:`EVERY` lines; it reads the process's resident memory (``/proc/self/statm``, a few µs) and
the C heap's bytes in use (glibc's ``mallinfo2``, where there is one), and raises a
:class:`~voxposer.errors.SandboxError` once either exceeds the run's start by more than the
sandbox's byte budget. Both count from the lowest reading of the run so far, not from its
start: the process may meanwhile free memory that generated code did not take (the cyclic
garbage collector, triggered by the code's allocations, frees what earlier work left), and that
must not hide what the code takes next. Resident memory alone misses allocations that reuse
memory the process freed earlier and kept (a long-lived process: a test run, a benchmark worker): the heap's
bytes in use count them. Memory that trusted callbacks take (inside ``suspend_time_limit``: a
nested LLM call loading a model) is not counted. Where ``/proc`` is missing the watch is off;
``SandboxConfig(isolation="process")`` adds an OS limit on top.
"""

from __future__ import annotations

import ctypes
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


class _MallInfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in (
        "arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks",
        "fordblks", "keepcost")]


def _mallinfo2() -> ctypes._CFuncPtr | None:  # type: ignore[name-defined]
    try:
        fn = ctypes.CDLL(None).mallinfo2
    except (OSError, AttributeError):
        return None
    fn.restype = _MallInfo2
    return fn


_MALLINFO2: Final = _mallinfo2()


def heap_bytes() -> int | None:
    """Bytes the C heap has in use (glibc's ``mallinfo2``: small blocks and mmapped ones);
    None where it is not available."""
    if _MALLINFO2 is None:
        return None
    info = _MALLINFO2()
    return int(info.uordblks + info.hblkhd)


def _state() -> list[list[int]]:
    """Per thread: one [start resident bytes, budget bytes, line counter, start heap bytes]
    per running execution (-1: not measured; the heap's start is read at the run's first
    check, see :func:`check`)."""
    if not hasattr(_local, "runs"):
        _local.runs = []
    return _local.runs


def start(budget_bytes: int) -> None:
    """A sandboxed execution begins: remember where resident memory stands."""
    now = resident_bytes()
    _state().append([now if now is not None else -1, int(budget_bytes), 0, -1])


def stop() -> None:
    """The innermost execution ended."""
    runs = _state()
    if runs:
        runs.pop()


def check() -> None:
    """Called per traced line; every :data:`EVERY` lines compares memory with the budget.

    The heap is first read at the run's first check, not at its start: ``mallinfo2`` walks
    the heap's free lists (milliseconds in a long-lived, fragmented process), and most
    generated programs (the map programs re-run at every replan) end before :data:`EVERY`
    lines, so they never pay for it; what the first lines took is missed by the heap measure
    only."""
    runs = _state()
    if not runs:
        return
    run = runs[-1]
    run[2] += 1
    if run[2] % EVERY:
        return
    rss, heap = resident_bytes(), heap_bytes()
    if run[3] < 0 and heap is not None:
        run[3] = heap
    run[0], run[3] = _lowest(run[0], rss), _lowest(run[3], heap)
    grown = max(_grown(run[0], rss), _grown(run[3], heap))
    if grown > run[1]:
        run[0], run[3] = _now(rss), _now(heap)  # raise once; the frames unwind
        raise SandboxError(
            f"memory limit: the generated code took {grown / 2**20:,.0f} MiB more than at its "
            f"start (or its lowest point since); the sandbox allows {run[1] / 2**20:,.0f} MiB in all")


def _lowest(start_bytes: int, now: int | None) -> int:
    """The new baseline: the lowest reading so far (the process may free what others left
    meanwhile: a garbage collection of earlier cycles; growth counts from there)."""
    return start_bytes if now is None or start_bytes < 0 else min(start_bytes, now)


def _grown(start_bytes: int, now: int | None) -> int:
    """Growth since ``start_bytes`` (0 where either is not measured)."""
    return 0 if now is None or start_bytes < 0 else now - start_bytes


def _now(value: int | None) -> int:
    return value if value is not None else -1


def watching_heap() -> bool:
    """Whether some running execution measures the heap (then trusted code's heap growth must
    be read, to be discounted)."""
    return any(run[3] >= 0 for run in _state())


def discount(grown_bytes: int, heap_grown_bytes: int) -> None:
    """Leave what trusted code took meanwhile out of every running budget: ``grown_bytes`` of
    resident memory and ``heap_grown_bytes`` of the C heap."""
    for run in _state():
        if run[0] >= 0:
            run[0] += grown_bytes
        if run[3] >= 0:
            run[3] += heap_grown_bytes


