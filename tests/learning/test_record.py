"""Resampling the executor's sampled path into the learner's waypoints."""

from __future__ import annotations

import numpy as np

from voxposer.learning.record import resample

Q = np.array([0.0, 0.0, 0.0, 1.0])


def _row(x: float, grip: float = 0.0, stage: int = 0) -> tuple:
    return (np.array([x, 0.0, 0.3]), Q, grip, stage)


def test_waypoints_are_at_most_the_spacing_apart_and_keep_the_ends() -> None:
    rows = [_row(0.0), _row(0.005), _row(0.012), _row(0.09), _row(0.095)]
    out = resample(rows, 0.02)
    xs = np.array([r[0][0] for r in out])
    assert xs[0] == 0.0 and xs[-1] == 0.095
    assert np.diff(xs).max() <= 0.02 + 1e-12
    assert np.all(np.diff(xs) >= 0)


def test_a_gripper_or_sub_task_change_is_held_for_one_more_waypoint() -> None:
    rows = [_row(0.0), _row(0.001), _row(0.002, grip=1.0), _row(0.003, grip=1.0),
            _row(0.004, grip=1.0, stage=1)]
    out = resample(rows, 0.02)
    grips = [r[2] for r in out]
    stages = [r[3] for r in out]
    assert grips == [0.0, 1.0, 1.0, 1.0, 1.0]
    assert stages == [0, 0, 0, 1, 1]
