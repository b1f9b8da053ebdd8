"""One benchmark episode: reset → the method runs the instruction → the task's check.

:func:`run_episode` never raises for what happens inside the episode: a program or execution
failure is the method failing (the check still judges the final state), and any other exception
(a bug) makes an ``error`` record with its traceback.
"""

from __future__ import annotations

import logging
import time
import traceback
from dataclasses import asdict, dataclass, field
from typing import Any

from voxposer.bench.config import Tolerances
from voxposer.bench.methods import get_method
from voxposer.bench.task import reset_episode
from voxposer.bench.tasks import get_task
from voxposer.bench.trace import TraceRecorder
from voxposer.errors import VoxPoserError
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class EpisodeJob:
    """Which episode to run and how.

    Attributes:
        task, split, seed: the episode.
        method: "voxposer" or "llm_primitives".
        llm: "reference" (hand-written programs) or a backend kind of ``LLMConfig``.
        max_time_s: simulated time limit of each ``execute`` call [s].
    """

    task: str
    split: str
    seed: int
    method: str = "voxposer"
    llm: str = "reference"
    max_time_s: float = 40.0

    @property
    def key(self) -> tuple[str, str, str, str, int]:
        """Identity used by ``--resume``."""
        return (self.method, self.llm, self.task, self.split, self.seed)


@dataclass
class EpisodeRecord:
    """One line of the results JSONL."""

    task: str
    split: str
    seed: int
    method: str
    llm: str
    instruction: str = ""
    attributes: dict[str, str] = field(default_factory=dict)
    success: bool = False
    reason: str = ""
    program_error: str | None = None
    error: str | None = None
    metrics: dict[str, float] = field(default_factory=dict)
    timings_s: dict[str, float] = field(default_factory=dict)
    sim_time_s: float = 0.0
    llm_calls: int = 0
    #: of ``llm_calls``, those answered by the response cache (a repeated identical request)
    llm_cached_calls: int = 0
    prompt_tokens: int = 0
    completion_tokens: int = 0
    #: what the LLM wrote, in call order: {"lmp", "query", "code"} (for failure analysis)
    programs: list[dict[str, str]] = field(default_factory=list)

    def to_json(self) -> dict[str, Any]:
        """A JSON-serialisable dict."""
        return asdict(self)


class CountingBackend(LLMBackend):
    """Wraps a backend, counts calls and tokens and keeps what it wrote."""

    def __init__(self, inner: LLMBackend) -> None:
        self.inner = inner
        self.name = inner.name
        self.calls = self.cached = self.prompt_tokens = self.completion_tokens = 0
        self.seconds = 0.0
        self.programs: list[dict[str, str]] = []

    @property
    def model(self) -> str:
        return self.inner.model

    def complete(self, request: LLMRequest) -> LLMResponse:
        response = self.inner.complete(request)
        self.calls += 1
        self.cached += bool(getattr(response, "cached", False))
        self.prompt_tokens += response.prompt_tokens
        self.completion_tokens += response.completion_tokens
        self.seconds += response.seconds
        query = request.messages[-1].content if request.messages else ""
        self.programs.append({"lmp": request.prefix_id or "", "query": query[-300:],
                              "code": response.text})
        return response


def run_episode(job: EpisodeJob, world: Any, backend: LLMBackend | None = None,
                tol: Tolerances | None = None) -> EpisodeRecord:
    """Run ``job`` in ``world``; ``backend`` answers LLM calls (None with ``llm="reference"``)."""
    tol = tol or Tolerances()
    rec = EpisodeRecord(job.task, job.split, job.seed, job.method, job.llm)
    t0 = time.perf_counter()
    try:
        task, method = get_task(job.task), get_method(job.method)
        setup = reset_episode(task, world, job.split, job.seed, tol)
        rec.instruction, rec.attributes = setup.instruction, dict(setup.attributes)
        t1 = time.perf_counter()
        if job.llm == "reference":
            backend = method.reference_backend(task, setup.attributes)
        if backend is None:
            raise VoxPoserError(f"episode {job.key} has no LLM backend")
        counting = CountingBackend(backend)
        sim0 = float(world.data.time)
        with TraceRecorder(world, task.tracked(setup.attributes)) as recorder:
            try:
                method.run(world, counting, setup, job.max_time_s)
            except VoxPoserError as err:
                rec.program_error = f"{type(err).__name__}: {err}"
        t2 = time.perf_counter()
        rec.sim_time_s = round(float(world.data.time) - sim0, 3)
        rec.llm_calls, rec.prompt_tokens = counting.calls, counting.prompt_tokens
        rec.llm_cached_calls = counting.cached
        rec.completion_tokens = counting.completion_tokens
        rec.programs = counting.programs
        verdict = task.check(world, recorder.trace(), setup.attributes, tol)
        rec.success, rec.reason = bool(verdict.success), verdict.reason
        rec.metrics = {k: round(float(v), 4) for k, v in verdict.metrics.items()}
        rec.timings_s = {"reset": round(t1 - t0, 3), "run": round(t2 - t1, 3),
                         "llm": round(counting.seconds, 3)}
    except Exception as exc:
        rec.success = False
        rec.error = "".join(traceback.format_exception(exc))
        rec.reason = f"error: {type(exc).__name__}: {exc}"
        log.warning("episode %s crashed: %s", job.key, exc)
    rec.timings_s["total"] = round(time.perf_counter() - t0, 3)
    return rec
