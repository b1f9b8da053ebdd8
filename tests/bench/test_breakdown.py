"""The error breakdown: failures of known cause are attributed to it (paper Fig. 4)."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from voxposer.bench.breakdown import attribute, check_rerunnable, failed_records
from voxposer.bench.breakdown_run import BREAKDOWN_FILE, break_down, load_run, pending
from voxposer.bench.episode import EpisodeJob, run_episode
from voxposer.bench.report_breakdown import summarise, write_breakdown
from voxposer.errors import ConfigError


def _blind_as_model(world) -> dict:
    """A failed episode whose model "forgot" the constraint: the constraint-blind control's
    programs (the reference minus its avoidance-style map), recorded as if a model wrote them."""
    rec = run_episode(EpisodeJob("move_to_pos_min_distance", "seen", 0, llm="reference-blind",
                                 seed_set="dev"), world).to_json()
    assert not rec["success"], rec["reason"]  # the control fails on this layout
    assert rec["programs"], "the run keeps what was written"
    return {**rec, "llm": "default", "perception": "ground-truth"}


def test_a_program_missing_its_constraint_map_is_a_specification_error(world) -> None:
    a = attribute(_blind_as_model(world), world)
    assert a.cause == "specification", a.note
    assert [s.step for s in a.steps] == ["reproduce", "specification"]
    assert not a.steps[0].success and a.steps[0].loose == 0  # replayed exactly, failed again
    assert a.steps[1].success


class _ShiftedBlocks:
    """A corrupted perceiver (a test double): every block is reported 10 cm from where it is."""

    SHIFT = np.array([0.10, 0.0, 0.0])

    def __init__(self, inner) -> None:
        self.inner = inner

    def __getattr__(self, name: str):
        return getattr(self.inner, name)

    def detect(self, name: str):
        obj = self.inner.detect(name)
        if not obj.name.endswith("block"):
            return obj
        steps = round(float(self.SHIFT[0]) / float(self.inner.grid.resolution))
        return dataclasses.replace(obj, position=obj.position + self.SHIFT,
                                   aabb=obj.aabb + self.SHIFT, points=obj.points + self.SHIFT,
                                   occupancy=np.roll(obj.occupancy, steps, axis=0))


def test_a_failure_of_a_corrupted_perception_is_a_perception_error(world, monkeypatch) -> None:
    import voxposer.pipeline as pipeline

    real = pipeline.simulated_perceiver

    def perceiver(world, perception, **kw):  # "ground-truth-noisy" stands for the broken one
        if perception == "ground-truth-noisy":
            return _ShiftedBlocks(real(world, "ground-truth"))
        return real(world, perception, **kw)

    monkeypatch.setattr(pipeline, "simulated_perceiver", perceiver)
    rec = {"task": "move_to_preposition", "split": "seen", "seed": 0, "method": "voxposer",
           "llm": "reference", "instructions": "seen", "seed_set": "dev",
           "perception": "ground-truth-noisy", "success": False}
    a = attribute(rec, world)
    assert a.cause == "perception", (a.note, [s.reason for s in a.steps])
    assert [s.step for s in a.steps] == ["reproduce", "perception"]
    assert not a.steps[0].success and a.steps[1].success


def test_a_failure_that_does_not_reproduce_is_unresolved(world) -> None:
    # a "failed" record of an episode the reference programs solve: nothing to blame
    rec = {"task": "move_to_pos_min_distance", "split": "seen", "seed": 0, "method": "voxposer",
           "llm": "reference", "instructions": "seen", "seed_set": "dev", "success": False}
    a = attribute(rec, world)
    assert a.cause == "unresolved" and "did not reproduce" in a.note
    assert len(a.steps) == 1


def test_records_that_cannot_be_re_run_name_what_they_lack() -> None:
    base = {"task": "push_to_pos", "split": "seen", "seed": 3, "method": "voxposer",
            "llm": "default", "instructions": "seen", "success": False}
    with pytest.raises(ConfigError, match="lacks 'programs'"):
        check_rerunnable(base)
    with pytest.raises(ConfigError, match="lacks split, seed"):
        check_rerunnable({"task": "push_to_pos", "method": "voxposer", "llm": "reference",
                          "instructions": "seen"})
    with pytest.raises(ConfigError, match="lacks 'unet_checkpoint'"):
        check_rerunnable({**base, "method": "unet_mp", "llm": "none"})
    check_rerunnable({**base, "llm": "reference"})  # reference programs need nothing recorded


def test_controls_are_not_broken_down() -> None:
    records = [{"llm": "reference-blind", "success": False}, {"llm": "default", "success": False},
               {"llm": "default", "success": True}]
    assert failed_records(records) == [records[1]]


def _episode(seed: int, success: bool, **kw) -> dict:
    return {"task": "push_to_pos", "split": "seen", "seed": seed, "method": "voxposer",
            "llm": "reference", "instructions": "seen", "success": success, **kw}


def _attribution(seed: int, cause: str) -> dict:
    return {**_episode(seed, False), "disturbed": False, "suite": "tasks",
            "perception": "ground-truth", "cause": cause, "note": "", "steps": [
                {"step": "reproduce", "success": False, "reason": "far | away"}]}


def test_summary_counts_every_cause_over_the_episodes(tmp_path: Path) -> None:
    records = [_episode(s, s >= 3) for s in range(10)]  # 3 failures of 10
    found = [_attribution(0, "dynamics"), _attribution(1, "specification"),
             _attribution(2, "specification")]
    (row,) = summarise(records, found).values()
    assert (row["episodes"], row["failures"], row["attributed"]) == (10, 3, 3)
    assert (row["dynamics"], row["specification"], row["perception"]) == (1, 2, 0)
    report = write_breakdown(records, found, tmp_path)
    text = report.read_text()
    assert "| 2 (20.0% / 67%) |" in text  # specification: of the episodes / of the failures
    assert "far / away" in text  # a reason's pipe does not break the table
    assert (tmp_path / "breakdown.png").stat().st_size > 5000


def test_a_run_continues_where_its_attributions_stopped(tmp_path: Path, world) -> None:
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    records = [_episode(0, False), _episode(1, False), _episode(2, True)]
    (run_dir / "episodes.jsonl").write_text("".join(json.dumps(r) + "\n" for r in records))
    (run_dir / BREAKDOWN_FILE).write_text(json.dumps(_attribution(0, "dynamics")) + "\n"
                                          + json.dumps(_attribution(1, "unresolved")) + "\n")
    run = load_run(run_dir)
    assert pending(run) == []  # both failures attributed: nothing re-runs
    (out,) = break_down([run], world)
    assert len(out.attributions) == 2
    with pytest.raises(ConfigError, match=r"no episodes\.jsonl"):
        load_run(tmp_path / "missing")


def _primitives_record() -> dict:
    # an LLM + Primitives program that does nothing (the task is not done)
    return {"task": "move_to_region", "split": "seen", "seed": 0, "method": "llm_primitives",
            "llm": "default", "instructions": "seen", "seed_set": "dev", "success": False,
            "programs": [{"lmp": "llm_primitives", "query": "q", "code": "pass"}]}


def test_an_llm_primitives_failure_is_fixed_by_its_reference_program(world) -> None:
    a = attribute(_primitives_record(), world)
    assert a.cause == "specification", a.note


def test_a_method_without_reference_programs_says_so(world, monkeypatch) -> None:
    from voxposer.bench.tasks.move_to_region import MoveToRegion

    monkeypatch.setattr(MoveToRegion, "primitives_reference", lambda self, attrs: None)
    a = attribute(_primitives_record(), world)
    assert a.cause == "unresolved"
    assert "could not be replaced" in a.note and "no reference programs" in a.note, a.note
