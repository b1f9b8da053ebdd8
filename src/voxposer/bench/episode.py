"""One benchmark episode: reset → the method runs the instruction → the task's check.

:func:`run_episode` never raises for what happens inside the episode: a program or execution
failure is the method failing (the check still judges the final state), a physics blow-up
(:class:`~voxposer.errors.SimulationUnstableError`) ends the episode as a failure with reason
"simulation unstable: …" (no check judges a NaN state; the next reset recovers the world), and
any other exception (a bug) makes an ``error`` record with its traceback.
"""

from __future__ import annotations

import logging
import time
import traceback
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.disturb import EpisodeDisturbance
from voxposer.bench.methods import BACKENDLESS_LLMS, REFERENCE_BLIND, get_method
from voxposer.bench.paraphrases import PhrasingSplit, paraphrase
from voxposer.bench.program_replay import QUERY_CHARS
from voxposer.bench.protocol import ADHOC, VAGUE_RELATIONAL
from voxposer.bench.push_dynamics import HEURISTIC, CountingPush, push_dynamics
from voxposer.bench.suites import TASKS_SUITE, suite_task
from voxposer.bench.task import reset_episode
from voxposer.bench.trace import TraceRecorder
from voxposer.bench.vague_relational import render, scene_blocks
from voxposer.bench.version import code_version
from voxposer.bench.videos import finish_video, start_video
from voxposer.errors import SimulationUnstableError, VoxPoserError
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class EpisodeJob:
    """Which episode to run and how.

    Attributes:
        task, split, seed: the episode.
        method: "voxposer", "llm_primitives" or "unet_mp".
        llm: "reference" (hand-written programs), "reference-blind" (their constraint-blind
            control) or a backend kind of ``LLMConfig``.
        max_time_s: simulated time limit of each ``execute`` call [s].
        instructions: "seen", "unseen" (the task's few-shot examples held out of the prompts)
            "paraphrased" (a reworded instruction: :mod:`voxposer.bench.paraphrases`) or
            "vague-relational" (its slots said vaguely or by relation:
            :mod:`voxposer.bench.vague_relational`).
        seed_set: the seed set ``seed`` comes from ("dev", "test", or "adhoc").
        disturbed: with the paper's disturbances (:mod:`voxposer.bench.disturb`).
        video: "none", "failures" or "all" (:mod:`voxposer.bench.videos`).
        out_dir: the output folder (videos go to its ``videos/``); None without videos.
        suite: the instruction suite ``task`` comes from ("tasks" or "multistep":
            :mod:`voxposer.bench.suites`).
        unet_checkpoint: the U-Net checkpoint's path (method "unet_mp"), else None.
        perception: how the robot finds objects (:data:`voxposer.pipeline.PERCEPTIONS`; None:
            this process's default, see :func:`voxposer.pipeline.use_perception`).
        dynamics: the pushing MPC's dynamics model
            (:data:`~voxposer.bench.push_dynamics.DYNAMICS`): "heuristic" (the
            paper's, :class:`~voxposer.planning.dynamics.TranslationPush`) or "simulator" (each
            sampled push simulated in a copy of the world: the error breakdown's counterfactual,
            :class:`~voxposer.bench.sim_dynamics.SimulatedPush`) or "learned" (``push_model``).
        push_model: the learned push model's file (dynamics "learned"), else None.
    """

    task: str
    split: str
    seed: int
    method: str = "voxposer"
    llm: str = "reference"
    max_time_s: float = 40.0
    instructions: str = "seen"
    seed_set: str = ADHOC
    disturbed: bool = False
    video: str = "none"
    out_dir: str | None = None
    suite: str = TASKS_SUITE
    unet_checkpoint: str | None = None
    perception: str | None = None
    dynamics: str = HEURISTIC
    push_model: str | None = None

    @property
    def key(self) -> tuple[str, str, str, str, str, int, bool]:
        """Identity used by ``--resume`` (static and disturbed episodes differ)."""
        return (self.method, self.llm, self.instructions, self.task, self.split, self.seed,
                self.disturbed)


@dataclass
class EpisodeRecord:
    """One line of the results JSONL."""

    task: str
    split: str
    seed: int
    method: str
    llm: str
    #: instruction split ("seen"/"unseen") and seed set ("dev"/"test"/"adhoc") of the run
    instructions: str = "seen"
    seed_set: str = ADHOC
    #: the code version (:mod:`voxposer.bench.version`): package content hash (the identity
    #: compared by --resume and the report), prompt-file hash, git commit and dirty flag
    code_hash: str = ""
    prompt_hash: str = ""
    git_commit: str | None = None
    git_dirty: bool | None = None
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
    #: run with the paper's disturbances, and what was applied when ({"kind", "target",
    #: "sim_time_s", "progress", …}; :mod:`voxposer.control.disturbance_schedule`)
    disturbed: bool = False
    disturbances: list[dict[str, Any]] = field(default_factory=list)
    #: the episode's MP4, relative to the output folder (None: not recorded or not kept)
    video: str | None = None
    #: intent checks: the post-conditions the plan stated, evaluated after their sub-tasks
    #: ({"subtask", "condition", "held", "measured", "error"}), and the run's own verdict —
    #: True when no sub-task failed and every evaluated post-condition held (None: the plan
    #: stated none), compared with ``success`` (the task's check) by the report
    intent: list[dict[str, Any]] = field(default_factory=list)
    intent_verdict: bool | None = None
    #: the instruction suite of ``task`` (:mod:`voxposer.bench.suites`)
    suite: str = TASKS_SUITE
    #: the trained model the method ran (unet_mp: its checkpoint's {"path", "sha256"} prefix)
    unet_checkpoint: dict[str, str] | None = None
    #: the pushing MPC's dynamics model (:data:`~voxposer.bench.push_dynamics.DYNAMICS`) and
    #: how many pushes it predicted
    #: (MPC steps; 0: the episode pushed nothing)
    dynamics: str = HEURISTIC
    push_predictions: int = 0

    def to_json(self) -> dict[str, Any]:
        """A JSON-serialisable dict."""
        return asdict(self)

    @classmethod
    def for_job(cls, job: EpisodeJob) -> EpisodeRecord:
        """An empty record of ``job``, stamped with this process's code version."""
        v = code_version()
        return cls(job.task, job.split, job.seed, job.method, job.llm,
                   instructions=job.instructions, seed_set=job.seed_set, code_hash=v.code_hash,
                   prompt_hash=v.prompt_hash, git_commit=v.commit, git_dirty=v.dirty,
                   disturbed=job.disturbed, suite=job.suite, dynamics=job.dynamics)


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
        return self._count(request, self.inner.complete(request))

    def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        responses = self.inner.complete_many(requests)
        return [self._count(q, r) for q, r in zip(requests, responses, strict=True)]

    def _count(self, request: LLMRequest, response: LLMResponse) -> LLMResponse:
        self.calls += 1
        self.cached += bool(getattr(response, "cached", False))
        self.prompt_tokens += response.prompt_tokens
        self.completion_tokens += response.completion_tokens
        self.seconds += response.seconds
        query = request.messages[-1].content if request.messages else ""
        self.programs.append({"lmp": request.prefix_id or "", "query": query[-QUERY_CHARS:],
                              "code": response.text})
        return response


def intent_verdict(intent: list[dict[str, Any]], failure: BaseException | None) -> bool | None:
    """The run's own verdict from its stated post-conditions: None when none was evaluated,
    else True when every one held and no sub-task failed."""
    checked = [r for r in intent if not r.get("error")]
    if not checked:
        return None
    return failure is None and all(bool(r["held"]) for r in checked)


def instability(failure: BaseException | None, world: Any) -> str | None:
    """Why the physics of ``world`` is not to be judged: the SimulationUnstableError behind
    ``failure`` (an LMP failure wraps it) or a NaN/inf state; None when it is sound."""
    seen: set[int] = set()
    err = failure
    while err is not None and id(err) not in seen:
        if isinstance(err, SimulationUnstableError):
            return str(err)
        seen.add(id(err))
        err = err.__cause__ or err.__context__
    data = getattr(world, "data", None)
    state = [getattr(data, name, ()) for name in ("qpos", "qvel")]
    if not all(np.all(np.isfinite(np.asarray(v, dtype=np.float64))) for v in state):
        return "the physics state holds NaN/inf values"
    return None


def run_episode(job: EpisodeJob, world: Any, backend: LLMBackend | None = None,
                tol: Tolerances | None = None) -> EpisodeRecord:
    """Run ``job`` in ``world``; ``backend`` answers LLM calls (None with reference programs);
    ``job.disturbed`` adds the paper's disturbances, ``job.video`` records an MP4."""
    tol = tol or Tolerances()
    rec = EpisodeRecord.for_job(job)
    t0 = time.perf_counter()
    video, disturbance = None, None
    try:
        task, method = suite_task(job.suite, job.task), get_method(job.method)
        setup = reset_episode(task, world, job.split, job.seed, tol)
        phrasing: PhrasingSplit = "test" if job.seed_set == "test" else "dev"  # on test seeds
        if job.instructions == "paraphrased":
            setup = replace(setup, instruction=paraphrase(
                task.name, setup.attributes, phrasing, job.seed))
        elif job.instructions == VAGUE_RELATIONAL:
            setup = replace(setup, instruction=render(
                task.name, setup.attributes, *scene_blocks(world), phrasing,
                job.seed).instruction)
        rec.instruction, rec.attributes = setup.instruction, dict(setup.attributes)
        t1 = time.perf_counter()
        if job.unet_checkpoint is not None:
            from voxposer.bench.unet_method import checkpoint_identity

            rec.unet_checkpoint = checkpoint_identity(job.unet_checkpoint)
        if job.llm in BACKENDLESS_LLMS:
            backend = method.reference_backend(task, setup.attributes,
                                               blind=job.llm == REFERENCE_BLIND)
        if backend is None:
            raise VoxPoserError(f"episode {job.key} has no LLM backend")
        counting = CountingBackend(backend)
        push_model = CountingPush(push_dynamics(job.dynamics, world, job.push_model))
        sim0 = float(world.data.time)
        if job.disturbed:
            disturbance = EpisodeDisturbance(world, task, setup.attributes)
        video = start_video(job, world)
        failure: VoxPoserError | None = None
        with TraceRecorder(world, task.tracked(setup.attributes)) as recorder:
            try:
                method.run(world, counting, setup, job.max_time_s, job.instructions,
                           make_disturber=disturbance, intents=rec.intent,
                           checkpoint=job.unet_checkpoint, perception=job.perception,
                           push_model=push_model)
            except VoxPoserError as err:
                rec.program_error = f"{type(err).__name__}: {err}"
                failure = err
        t2 = time.perf_counter()
        rec.sim_time_s = round(float(world.data.time) - sim0, 3)
        rec.llm_calls, rec.prompt_tokens = counting.calls, counting.prompt_tokens
        rec.llm_cached_calls = counting.cached
        rec.completion_tokens = counting.completion_tokens
        rec.programs = counting.programs
        rec.push_predictions = push_model.calls
        rec.intent_verdict = intent_verdict(rec.intent, failure)
        unstable = instability(failure, world)
        if unstable is not None:
            rec.success, rec.reason = False, f"simulation unstable: {unstable}"
        else:
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
    rec.disturbances = [] if disturbance is None else disturbance.applied
    rec.video = finish_video(job, video, rec.success)
    rec.timings_s["total"] = round(time.perf_counter() - t0, 3)
    return rec
