"""Detected objects as generated code sees them: each detection is its own copy, so a program
that changes a position in place (a common way of writing an offset) works and leaves the scene
and the next detection untouched; the large occupancy array stays read-only."""

from __future__ import annotations

import numpy as np
import pytest

from voxposer.lmp.api import LMPAPI
from voxposer.lmp.sandbox import Sandbox
from voxposer.lmp.scene import make_tabletop_scene

OFFSET_CODE = """
obj = detect('blue block')
p = obj.position
p[2] += 5
w = obj.position_world
w[0] = 9.0
again = detect('blue block')
"""


def test_a_program_may_offset_a_detected_position_in_place() -> None:
    api = LMPAPI(make_tabletop_scene())
    before = api.detect("blue block")
    out = Sandbox().run(OFFSET_CODE, dict(api.namespace()))
    assert out["p"][2] == before.position[2] + 5  # the program's own copy changed
    assert out["w"][0] == 9.0
    np.testing.assert_array_equal(out["again"].position, before.position)  # perception did not
    np.testing.assert_array_equal(out["again"].position_world, before.position_world)
    np.testing.assert_array_equal(api.detect("blue block").position_world,
                                  before.position_world)


def test_the_occupancy_of_a_detection_stays_read_only() -> None:
    api = LMPAPI(make_tabletop_scene())
    with pytest.raises(ValueError, match="read-only"):
        Sandbox().run("o = detect('blue block')\no.occupancy[0, 0, 0] = True",
                      dict(api.namespace()))
