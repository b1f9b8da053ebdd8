"""The disturbances ``voxposer run --disturb`` writes into summary.json (and the benchmark into
its records) are structured fields: the kind, the object disturbed, its position or opening before
and after, the force, and when; plain JSON values, whatever the world returned."""

from __future__ import annotations

import json

import numpy as np
import pytest

from voxposer.control.disturbance_schedule import applied_record
from voxposer.envs.disturbances import Disturbance


def _roundtrip(entry: dict) -> dict:
    assert json.loads(json.dumps(entry, allow_nan=False)) == entry
    return entry


def test_a_push_names_the_robot_link_position_and_force() -> None:
    done = Disturbance("force", "panda_link5", np.array([0.1, -0.2, 0.4]),
                       np.array([12.0, -20.0, 3.0]), 0.3, 1.234567)
    entry = _roundtrip(applied_record("push_robot", "robot", "gripper", 1.2345, 0.2, done))
    assert entry["kind"] == "push_robot" and entry["object"] == "robot"
    assert entry["link"] == "panda_link5" and entry["entity"] == "gripper"
    assert entry["position_before_m"] == [0.1, -0.2, 0.4] and entry["position_after_m"] is None
    assert entry["force_n"] == [12.0, -20.0, 3.0] and entry["duration_s"] == 0.3
    assert entry["sim_time_s"] == pytest.approx(1.2345, abs=1e-3)
    assert entry["progress"] == 0.2 and entry["opening_before_m"] is None


def test_a_displaced_block_has_both_positions() -> None:
    done = Disturbance("displace", "blue block", np.array([0.0, -0.05, 0.025]),
                       np.array([0.12, 0.04, 0.025]), 0.0, 3.0)
    entry = _roundtrip(applied_record("displace_object", "blue block", "blue block", 3.0, None,
                                      done))
    assert entry["object"] == "blue block" and entry["progress"] is None
    assert entry["position_before_m"] == [0.0, -0.05, 0.025]
    assert entry["position_after_m"] == [0.12, 0.04, 0.025]
    assert entry["force_n"] is None and entry["link"] is None
    assert all(not isinstance(v, np.generic) for v in entry["position_after_m"])


def test_a_pulled_drawer_has_its_opening_and_the_pull() -> None:
    done = Disturbance("revert", "top drawer", np.array([-0.0]), np.array([0.0, -40.2, 0.0]),
                       0.1, 6.4)
    entry = _roundtrip(applied_record("revert_progress", "top drawer", "top drawer handle", 6.43,
                                      0.591, done))
    assert entry["object"] == "top drawer" and entry["opening_before_m"] == 0.0
    assert str(entry["opening_before_m"]) == "0.0"  # not "-0.0"
    assert entry["opening_after_m"] is None  # physics decides how far it opens
    assert entry["force_n"] == [0.0, -40.2, 0.0] and entry["position_before_m"] is None
    # the keys written before these fields existed stay, for older readers
    assert entry["target"] == "top drawer" and entry["after"] == [0.0, -40.2, 0.0]
