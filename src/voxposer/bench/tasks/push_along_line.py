"""Task "push the [obj] along the [line]" (Object Interactions).

Reset: the line lies in the middle of the table at a random yaw; the block starts on the line's
axis 6.5–8 cm beyond one end (6.5–8 cm: the layout keeps blocks clear of lines), the end in front
of x = −0.36 m where one of them is behind it. Success: the block's centre stays within
``line_band_m`` of the line's axis the whole time, advances at least ``line_progress_m`` along it
and ends on the line (between its ends).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import sample_xy
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, one_subtask, segment_clear
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout

#: Line length [m] (``WorldConfig.line_length``).
LINE_LENGTH = 0.20
#: The block starts at the end of the line in front of this x [m]: pushing a block toward +x
#: from farther back puts the hand within ≈ 10 cm of the robot's base, where the Panda cannot
#: hold it top-down above the block (see :mod:`voxposer.envs.places`).
BACK_LIMIT_X = -0.36


def _axis(yaw: float) -> np.ndarray:
    return np.array([math.cos(yaw), math.sin(yaw)])


class PushAlongLine(BenchTask):
    name = "push_along_line"
    category = "Object Interactions"
    template = "push the [obj] along the [line]"
    paper_row = "push the [obj] along the [line]"

    def tracked(self, attrs: dict[str, str]) -> tuple[str, ...]:
        return (attrs["obj"],)

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        c = np.asarray(sample_xy(rng, (-0.26, -0.15), (-0.04, 0.15)))
        yaw = float(rng.uniform(0.0, math.pi))
        end = 1.0 if rng.uniform() < 0.5 else -1.0
        offset = _axis(yaw) * (LINE_LENGTH / 2 + float(rng.uniform(0.065, 0.08)))
        if c[0] + end * offset[0] < BACK_LIMIT_X:  # the other end: the hand must get behind it
            end = -end
        start = c + end * offset
        return block_layout({attrs["line"]: (float(c[0]), float(c[1]), yaw),
                             attrs["obj"]: (float(start[0]), float(start[1]))})

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        block = tuple(world.object_position(attrs["obj"])[:2])
        c = world.object_position(attrs["line"])[:2]
        far = tuple(2 * c - np.asarray(block))
        return segment_clear(block, far, 0.09)

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        c = world.object_position(attrs["line"])[:2]
        u = _axis(world.object_yaw(attrs["line"]))
        rel = trace.objects[attrs["obj"]][:, :2] - c
        along = rel @ u
        lateral = float(np.max(np.abs(rel @ np.array([-u[1], u[0]]))))
        sign = -np.sign(along[0]) or 1.0
        progress = float(sign * (along[-1] - along[0]))
        on_line = abs(float(along[-1])) <= LINE_LENGTH / 2
        ok = lateral <= tol.line_band_m and progress >= tol.line_progress_m and on_line
        return Verdict(ok, f"strayed at most {lateral * 100:.1f} cm from the line, advanced "
                       f"{progress * 100:.1f} cm, ends {'on' if on_line else 'off'} the line",
                       {"lateral": lateral, "progress": progress, "along_end": float(along[-1])})

    def reference(self, attrs: dict[str, str]) -> Programs:
        obj, line = attrs["obj"], attrs["line"]
        subtask = f"push the {obj} along the {line}"
        query = f"the center of the {line} at the height of the {obj}"
        progs = one_subtask(Programs(), self.instruction(attrs), subtask, reset=True)
        progs.add("composer", subtask, f"movable = parse_query_obj('{obj}')",
                  f"affordance_map = get_affordance_map('{query}')",
                  "execute(movable, affordance_map=affordance_map)")
        return progs.add("get_affordance_map", query,
                         "affordance_map = get_empty_affordance_map()",
                         f"line = parse_query_obj('{line}')", f"block = parse_query_obj('{obj}')",
                         "x, y, _ = line.position", "affordance_map[x, y, block.position[2]] = 1",
                         "ret_val = affordance_map")
