"""The error breakdown of paper Sec. 4.4 / Fig. 4: why did each failed episode fail?

Every failed episode of a run is re-run on its own seed with its components replaced one after
the other by their ground truth, cumulatively; the failure goes to the first component whose
replacement makes the episode succeed:

1. **reproduce** — nothing replaced: the recorded programs (:mod:`voxposer.bench.program_replay`)
   replayed with the run's perception and the heuristic dynamics. An episode that now succeeds
   did not fail for a reason a component explains: "unresolved" (not reproduced).
2. **perception** — the simulator's ground-truth segmentation instead of the run's perception
   (skipped when the run already had it, and for U-Net + MP, which has no perception module:
   paper footnote 5).
3. **dynamics** — the simulator as the pushing MPC's dynamics model
   (:class:`~voxposer.bench.sim_dynamics.SimulatedPush`) instead of the heuristic (skipped when
   the episode pushed nothing, and for LLM + Primitives, which plans no pushes: footnote 4).
4. **specification** — the task's reference programs instead of what the model wrote (for
   U-Net + MP: the reference programs' value maps, the map it was trained to predict, run by
   VoxPoser's planner and executor; skipped for a run of the reference programs themselves).

An episode still failing with everything replaced is "unresolved" (the planner, the
controller or the check: :data:`CAUSES`). Each re-run is an ordinary
:func:`~voxposer.bench.episode.run_episode` on the current code.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field, replace
from typing import Any, Final

from voxposer.bench.episode import EpisodeJob, EpisodeRecord, run_episode
from voxposer.bench.methods import BACKENDLESS_LLMS, REFERENCE, REFERENCE_BLIND
from voxposer.bench.program_replay import RecordedProgramsBackend
from voxposer.bench.push_dynamics import HEURISTIC, SIMULATOR
from voxposer.bench.unet_method import UNET_MP
from voxposer.errors import ConfigError

#: the re-runs, in order.
STEPS: Final = ("reproduce", "perception", "dynamics", "specification")
#: what a failure is attributed to.
CAUSES: Final = ("perception", "dynamics", "specification", "unresolved")
#: the ground-truth perception.
GROUND_TRUTH: Final = "ground-truth"
#: record fields a re-run needs.
REQUIRED: Final = ("task", "split", "seed", "method", "llm", "instructions")
#: simulated time limit of each ``execute`` call when a record does not say [s]
#: (``voxposer bench --max-time``'s default).
DEFAULT_MAX_TIME_S: Final = 40.0


@dataclass
class StepOutcome:
    """One re-run of a failed episode.

    Attributes:
        step: one of :data:`STEPS`.
        success, reason: the task check's verdict.
        program_error: why the method stopped, if it did.
        loose: programs replayed for a request the original run did not make.
        pushes: pushes the MPC planned (0: the episode pushed nothing).
        wall_s: the re-run's wall time [s].
    """

    step: str
    success: bool
    reason: str
    program_error: str | None = None
    loose: int = 0
    pushes: int = 0
    wall_s: float = 0.0


@dataclass
class Attribution:
    """A failed episode's cause, with the re-runs that found it (a line of
    ``breakdown.jsonl``)."""

    task: str
    split: str
    seed: int
    method: str
    llm: str
    instructions: str
    disturbed: bool
    suite: str
    perception: str
    cause: str
    note: str
    steps: list[StepOutcome] = field(default_factory=list)
    code_hash: str = ""

    @property
    def key(self) -> tuple[Any, ...]:
        """The episode's identity (as :attr:`EpisodeJob.key`, plus the suite)."""
        return (self.method, self.llm, self.instructions, self.task, self.split, self.seed,
                self.disturbed, self.suite)

    def to_json(self) -> dict[str, Any]:
        """A JSON-serialisable dict."""
        return asdict(self)


def record_key(rec: dict[str, Any]) -> tuple[Any, ...]:
    """:attr:`Attribution.key` of a benchmark record."""
    return (rec["method"], rec["llm"], rec.get("instructions", "seen"), rec["task"],
            rec["split"], int(rec["seed"]), bool(rec.get("disturbed", False)),
            rec.get("suite", "tasks"))


def check_rerunnable(rec: dict[str, Any]) -> None:
    """Raise ConfigError naming what a failed record lacks for its re-runs: the episode's
    identity, the programs a model wrote (records before they were kept), a U-Net checkpoint."""
    where = f"episode {rec.get('task', '?')}/{rec.get('split', '?')}/seed {rec.get('seed', '?')}"
    missing = [k for k in REQUIRED if k not in rec]
    if missing:
        raise ConfigError(f"{where} lacks {', '.join(missing)}, needed to re-run it")
    if rec["llm"] not in BACKENDLESS_LLMS and not rec.get("programs"):
        raise ConfigError(f"{where} ({rec['method']}/{rec['llm']}) lacks 'programs', the "
                          "programs its model wrote, needed to replay them; re-run the "
                          "benchmark with this version to record them")
    if rec["method"] == UNET_MP and not (rec.get("unet_checkpoint") or {}).get("path"):
        raise ConfigError(f"{where} ({UNET_MP}) lacks 'unet_checkpoint', the checkpoint's "
                          "path, needed to re-run the U-Net")


def base_job(rec: dict[str, Any], max_time_s: float = DEFAULT_MAX_TIME_S) -> EpisodeJob:
    """The job that re-runs ``rec`` as it ran (heuristic dynamics)."""
    ckpt = (rec.get("unet_checkpoint") or {}).get("path")
    return EpisodeJob(rec["task"], rec["split"], int(rec["seed"]), method=rec["method"],
                      llm=rec["llm"], max_time_s=max_time_s, instructions=rec["instructions"],
                      seed_set=rec.get("seed_set", "adhoc"),
                      disturbed=bool(rec.get("disturbed", False)),
                      suite=rec.get("suite", "tasks"), unet_checkpoint=ckpt,
                      perception=rec.get("perception", GROUND_TRUTH), dynamics=HEURISTIC)


def _specification_job(job: EpisodeJob) -> EpisodeJob | None:
    """``job`` with the reference programs instead of what the method specified (None: it ran
    them already)."""
    if job.llm == REFERENCE:
        return None
    if job.method == UNET_MP:
        return replace(job, method="voxposer", llm=REFERENCE, unet_checkpoint=None)
    return replace(job, llm=REFERENCE)


def attribute(rec: dict[str, Any], world: Any, *, max_time_s: float = DEFAULT_MAX_TIME_S
              ) -> Attribution:
    """Re-run the failed episode ``rec`` (a benchmark record) and attribute its failure (see the
    module docs); ``world`` is a tabletop world the re-runs reset."""
    check_rerunnable(rec)
    job = base_job(rec, max_time_s)
    out = Attribution(job.task, job.split, job.seed, job.method, job.llm, job.instructions,
                      job.disturbed, job.suite, job.perception or GROUND_TRUTH, "unresolved",
                      "")

    def rerun(step: str, j: EpisodeJob) -> EpisodeRecord:
        """Run ``j``, note it in ``out.steps`` as ``step``; returns its record."""
        backend = None
        if j.llm not in BACKENDLESS_LLMS:
            backend = RecordedProgramsBackend(rec["programs"])
        t0 = time.perf_counter()
        r = run_episode(j, world, backend)
        outcome = StepOutcome(step, bool(r.success), r.reason, r.program_error,
                              getattr(backend, "loose", 0), r.push_predictions,
                              round(time.perf_counter() - t0, 2))
        out.steps.append(outcome)
        out.code_hash = r.code_hash
        return r

    first = rerun("reproduce", job)
    if first.success:
        out.note = "the failure did not reproduce (the re-run as it ran succeeded)"
        return out
    pushed = first.push_predictions > 0
    if job.perception != GROUND_TRUTH and job.method != UNET_MP:
        job = replace(job, perception=GROUND_TRUTH)
        result = rerun("perception", job)
        pushed = result.push_predictions > 0
        if result.success:
            out.cause, out.note = "perception", "succeeds with ground-truth perception"
            return out
    if pushed and job.method != "llm_primitives":
        job = replace(job, dynamics=SIMULATOR)
        if rerun("dynamics", job).success:
            out.cause, out.note = "dynamics", "succeeds with the simulator as dynamics model"
            return out
    spec = _specification_job(job)
    if spec is not None:
        result = rerun("specification", spec)
        if result.success:
            out.cause = "specification"
            out.note = "succeeds with the reference programs"
            return out
        if result.error is not None:  # it crashed: e.g. no reference programs for the method
            out.note = f"the specification could not be replaced ({result.reason})"
            return out
    replaced = [s.step for s in out.steps[1:]]
    out.note = ("fails with " + ", ".join(replaced) + " replaced" if replaced
                else "no component to replace")
    return out


def failed_records(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The failed records of a run that a breakdown attributes (the constraint-blind controls
    are meant to fail, so they are not broken down)."""
    return [r for r in records if not r.get("success") and r.get("llm") != REFERENCE_BLIND]


__all__ = ["CAUSES", "STEPS", "Attribution", "StepOutcome", "attribute", "base_job",
           "check_rerunnable", "failed_records", "record_key"]
