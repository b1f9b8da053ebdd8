"""The inline sandbox counts memory: wide dtypes by their bytes, many small allocations in all."""

from __future__ import annotations

import gc

import numpy as np
import pytest

from voxposer.errors import SandboxError
from voxposer.lmp.sandbox import Sandbox, SandboxConfig, suspend_time_limit
from voxposer.lmp.sandbox_memory import resident_bytes

SMALL = SandboxConfig(max_elements=1_000_000)  # 8 MB of elements, 8 MiB of growth


def test_astype_to_a_wide_dtype_counts_its_bytes() -> None:
    sandbox = Sandbox(SMALL)
    sandbox.run("a = np.zeros(500_000)\nb = a.astype(np.float64)", {})  # 8 bytes: as many
    with pytest.raises(SandboxError, match=r"size limit: ndarray\.astype"):
        sandbox.run("a = np.zeros(500_000)\nb = a.astype(np.complex256)", {})  # 32 bytes
    with pytest.raises(SandboxError, match=r"size limit: np\.zeros"):
        sandbox.run("b = np.zeros(500_000, dtype=np.complex256)", {})


@pytest.mark.skipif(resident_bytes() is None, reason="no /proc/self/statm on this system")
def test_many_small_allocations_hit_the_memory_limit() -> None:
    gc.collect()  # what earlier tests left in cycles is not freed halfway through this run
    sandbox = Sandbox(SMALL)
    sandbox.run("rows = [[0] * 100 for _ in range(1000)]", {})  # 100k items: well inside
    with pytest.raises(SandboxError, match="memory limit"):  # 40M items, 1k each: ~320 MB
        sandbox.run("rows = [[0] * 1000 for _ in range(40_000)]", {})
    sandbox.run("x = 1", {})  # the next run starts afresh


@pytest.mark.skipif(resident_bytes() is None, reason="no /proc/self/statm on this system")
def test_memory_trusted_callbacks_take_is_not_counted() -> None:
    def load_model() -> np.ndarray:  # e.g. a nested LLM call that loads weights
        with suspend_time_limit():
            return np.ones(8_000_000)  # 64 MB, eight times the generated code's budget

    out = Sandbox(SMALL).run("w = load_model()\nfor i in range(2000):\n    y = i * 2", {
        "load_model": load_model})
    assert out["w"].size == 8_000_000


@pytest.mark.skipif(resident_bytes() is None, reason="no /proc/self/statm on this system")
def test_memory_the_process_freed_and_kept_is_counted_when_reused() -> None:
    # a long-lived process (a test run, a benchmark worker) keeps what it freed: generated
    # code that reuses it does not grow the resident memory, yet it takes the same bytes
    freed = [[0] * 1000 for _ in range(40_000)]
    pinned = freed[::50]  # a live block every 400 kB: the heap cannot give the rest back
    del freed
    sandbox = Sandbox(SMALL)
    with pytest.raises(SandboxError, match="memory limit"):
        sandbox.run("rows = [[0] * 1000 for _ in range(40_000)]", {})
    assert len(pinned) == 800


@pytest.mark.skipif(resident_bytes() is None, reason="no /proc/self/statm on this system")
def test_memory_the_process_frees_meanwhile_does_not_hide_growth() -> None:
    # the garbage collector, run by the generated code's allocations, may free what earlier
    # work left (320 MB here, freed after the watch's first reading): growth counts from there
    left = [np.ones(1_000_000) for _ in range(40)]

    def free_what_others_left() -> None:  # trusted, but not a suspend_time_limit callback
        left.clear()

    code = "for i in range(300):\n    y = i\nfree()\nrows = [[0] * 1000 for _ in range(40_000)]"
    with pytest.raises(SandboxError, match="memory limit"):
        Sandbox(SMALL).run(code, {"free": free_what_others_left})
    assert not left
