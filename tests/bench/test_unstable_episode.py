"""A physics blow-up in the middle of an episode (SimulationUnstableError, raised by the world's
own check of its state) ends the episode as a failure whose reason says so, without a check
judging a NaN state; the next episode in the same world runs normally."""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from voxposer.bench.episode import EpisodeJob, run_episode
from voxposer.bench.failure_modes import failure_mode


def test_a_blow_up_ends_the_episode_with_a_reason(world: Any, monkeypatch) -> None:
    advance = world.advance
    calls = {"n": 0}

    def diverging(nsteps: int) -> None:
        calls["n"] += 1
        if calls["n"] == 50:  # into the motion: the state turns NaN
            world.data.qvel[0] = np.nan
        advance(nsteps)

    monkeypatch.setattr(world, "advance", diverging)
    rec = run_episode(EpisodeJob("move_to_region", "seen", 0), world)
    assert calls["n"] >= 50
    assert not rec.success and rec.error is None
    assert rec.reason.startswith("simulation unstable: simulation became unstable at t=")
    assert "SimulationUnstableError" in (rec.program_error or "")
    assert rec.metrics == {}
    assert json.loads(json.dumps(rec.to_json()))["reason"] == rec.reason
    assert "SimulationUnstableError" in failure_mode(rec.to_json())
    monkeypatch.undo()
    again = run_episode(EpisodeJob("move_to_region", "seen", 1), world)
    assert again.error is None and again.success, again.reason
