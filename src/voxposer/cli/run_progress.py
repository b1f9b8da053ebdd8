"""The live terminal panel of ``voxposer run``: the current sub-task, the LLM calls, the
replanning rate and the distance to the target, and the backend wrapper that feeds it."""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from rich.table import Table


class RunProgress:
    """The live terminal panel and the counters behind it (a rich renderable).

    Attributes:
        instruction: the instruction being carried out.
        subtask: the sub-task being executed ("planning" before the first).
        llm: what the language model is doing ("idle", "asking <lmp>…").
        llm_calls: LLM calls answered so far.
        replans: plans made so far; ``hz`` is the last replanning rate [Hz].
        distance: distance to the current target [m] (NaN: none yet).
        started: ``time.perf_counter()`` when the panel was made [s].
    """

    def __init__(self, instruction: str) -> None:
        self.instruction = instruction
        self.subtask = "planning"
        self.llm = "idle"
        self.llm_calls = 0
        self.replans = 0
        self.hz = 0.0
        self.distance = float("nan")
        self.started = time.perf_counter()

    def __rich__(self) -> Table:
        table = Table.grid(padding=(0, 2))
        table.add_column(style="bold cyan")
        table.add_column()
        table.add_row("instruction", self.instruction)
        table.add_row("sub-task", self.subtask)
        table.add_row("LLM", f"{self.llm} ({self.llm_calls} calls)")
        table.add_row("replanning", f"{self.replans} plans, {self.hz:.1f} Hz")
        table.add_row(
            "to target", "—" if np.isnan(self.distance) else f"{self.distance * 100:.1f} cm"
        )
        table.add_row("elapsed", f"{time.perf_counter() - self.started:.0f} s")
        return table


def progress_backend(backend: Any, progress: RunProgress) -> Any:
    """Wrap ``backend`` so the panel shows each LLM call while it runs."""
    from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse

    class ProgressBackend(LLMBackend):
        name = backend.name

        @property
        def model(self) -> str:
            return str(backend.model)

        def complete(self, request: LLMRequest) -> LLMResponse:
            progress.llm = f"asking {request.prefix_id or 'model'}…"
            try:
                return backend.complete(request)
            finally:
                progress.llm_calls += 1
                progress.llm = "idle"

        def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
            progress.llm = f"asking {len(requests)} programs together…"
            try:
                return list(backend.complete_many(requests))
            finally:
                progress.llm_calls += len(requests)
                progress.llm = "idle"

        def close(self) -> None:
            backend.close()

    return ProgressBackend()


__all__ = ["RunProgress", "progress_backend"]
