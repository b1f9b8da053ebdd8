"""Task "push the [obj] along the [line]" (Object Interactions).

"Along the line" means the block travels on the line for most of its length: success needs the
block's centre to cover at least ``line_progress_m`` (70% of the 20 cm line) along it without
leaving ``line_band_m`` of its axis, and to end on the line (within the band,
between its ends + 2 cm).

Reset (so that the constraint binds): the line lies in the middle of the table along x or y
(± 9°); the block starts beside its back (x-lines) or left (y-lines) end — the *near* end — 7–8.5
cm off the axis (the layout keeps blocks clear of lines), level with that end. A correct program
brings the block onto the line near that end (4 cm in) and then pushes it along to the far end; pushing
it straight to the far end (the constraint-blind control: the same programs without the first
push) cuts across and meets the line only for its last part. (Starting at the back end keeps the
hand in front of x = −0.36 m, see ``BACK_LIMIT_X``.)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from voxposer.bench.config import Tolerances
from voxposer.bench.measures import sample_xy
from voxposer.bench.primitives_programs import primitives_program, push_lines
from voxposer.bench.programs import Programs
from voxposer.bench.task import BenchTask, Verdict
from voxposer.bench.tasks._common import block_layout, segment_clear
from voxposer.bench.trace import Trace
from voxposer.envs.layout import SceneLayout
from voxposer.geometry.line_progress import on_line_progress

#: Line length [m] (``WorldConfig.line_length``).
LINE_LENGTH = 0.20
#: The block is never pushed toward +x from behind this x [m]: the hand would come within
#: ≈ 10 cm of the robot's base, where the Panda cannot hold it top-down above the block.
BACK_LIMIT_X = -0.36
#: Where a correct first push meets the line: this far in from its near end [cm].
ENTRY_CM = 4
#: How far beside the line's axis the block starts (lo, hi) [m].
OFFSET_M = (0.07, 0.085)


def _axis(yaw: float) -> np.ndarray:
    return np.array([math.cos(yaw), math.sin(yaw)])


class PushAlongLine(BenchTask):
    name = "push_along_line"
    category = "Object Interactions"
    template = "push the [obj] along the [line]"
    paper_row = "push the [obj] along the [line]"
    constraint = "a first push onto the line's near end"

    def tracked(self, attrs: dict[str, str]) -> tuple[str, ...]:
        return (attrs["obj"],)

    def layout(self, rng: np.random.Generator, attrs: dict[str, str]) -> SceneLayout:
        c = np.asarray(sample_xy(rng, (-0.20, -0.12), (-0.06, 0.12)))
        yaw = int(rng.integers(2)) * math.pi / 2 + float(rng.uniform(-0.15, 0.15))
        u, n = _axis(yaw), _axis(yaw + math.pi / 2)
        side = 1.0 if rng.uniform() < 0.5 else -1.0
        start = (c - u * (LINE_LENGTH / 2 - float(rng.uniform(0.0, 0.02)))
                 + side * n * float(rng.uniform(*OFFSET_M)))
        return block_layout({attrs["line"]: (float(c[0]), float(c[1]), yaw),
                             attrs["obj"]: (float(start[0]), float(start[1]))})

    def _frame(self, world: Any, attrs: dict[str, str]) -> tuple[np.ndarray, np.ndarray]:
        """The line's centre (x, y) [m] and unit axis."""
        return world.object_position(attrs["line"])[:2], _axis(world.object_yaw(attrs["line"]))

    def keep_clear(self, world: Any, attrs: dict[str, str]
                   ) -> list[tuple[tuple[float, float], float]]:
        c, u = self._frame(world, attrs)
        block = world.object_position(attrs["obj"])[:2]
        near = c + u * np.sign((block - c) @ u) * LINE_LENGTH / 2
        far = 2 * c - near
        return (segment_clear(tuple(block), tuple(near), 0.09)
                + segment_clear(tuple(near), tuple(far), 0.09))

    def check(self, world: Any, trace: Trace, attrs: dict[str, str], tol: Tolerances) -> Verdict:
        c, u = self._frame(world, attrs)
        rel = trace.objects[attrs["obj"]][:, :2] - c
        along, lateral = rel @ u, np.abs(rel @ np.array([-u[1], u[0]]))
        progress = on_line_progress(along, lateral, tol.line_band_m)
        on_end = (lateral[-1] <= tol.line_band_m
                  and abs(float(along[-1])) <= LINE_LENGTH / 2 + 0.02)
        ok = progress >= tol.line_progress_m and on_end
        return Verdict(ok, f"travelled {progress * 100:.1f} cm on the line, ends "
                       f"{'on' if on_end else 'off'} it ({lateral[-1] * 100:.1f} cm from its "
                       "axis)", {"progress": progress, "lateral_end": float(lateral[-1]),
                                 "along_end": float(along[-1])})

    def _programs(self, attrs: dict[str, str], blind: bool) -> Programs:
        obj, line = attrs["obj"], attrs["line"]
        steps = ["far"] if blind else ["near", "far"]
        subtasks = [f"push the {obj} to the {w} end of the {line}" for w in steps]
        progs = Programs()
        progs.add("planner", self.instruction(attrs), *[f"composer('{s}')" for s in subtasks],
                  "composer('back to default pose')")
        progs.add("composer", "back to default pose", "reset_to_default_pose()")
        for word, subtask in zip(steps, subtasks, strict=True):
            query = f"the {word} end of the {line} at the height of the {obj}"
            progs.add("composer", subtask, f"movable = parse_query_obj('{obj}')",
                      f"affordance_map = get_affordance_map('{query}')",
                      "execute(movable, affordance_map=affordance_map)")
            # the near end's point lies ENTRY_CM inside the line: the block meets the line
            # at a slant there instead of being pushed sideways onto its very end; ends on the
            # line's own axis (end_of), not its box's (a line at a slant)
            end = f"end_of(line, 'low', cm_in={ENTRY_CM})" if word == "near" else "end_of(line, 'high')"
            progs.add("get_affordance_map", query, "affordance_map = get_empty_affordance_map()",
                      f"line = parse_query_obj('{line}')", f"block = parse_query_obj('{obj}')",
                      f"x, y, _ = {end}", "affordance_map[x, y, block.position[2]] = 1",
                      "ret_val = affordance_map")
        return progs

    def blind(self, attrs: dict[str, str]) -> Programs:
        return self._programs(attrs, blind=True)

    def reference(self, attrs: dict[str, str]) -> Programs:
        return self._programs(attrs, blind=False)

    def primitives_reference(self, attrs: dict[str, str]) -> Programs:
        obj, line = attrs["obj"], attrs["line"]
        return primitives_program(self.instruction(attrs), [
            f"line = detect('{line}')", f"block = detect('{obj}')",
            "lo, hi = line.aabb",
            "k = 0 if hi[0] - lo[0] > hi[1] - lo[1] else 1",  # the line's axis
            "u = np.zeros(2)", "u[k] = 1.0",
            "half = (hi[k] - lo[k]) / 2",
            "s = np.sign(block.position[k] - line.position[k])",  # toward its near end
            f"entry = line.position[:2] + s * (half - {ENTRY_CM / 100}) * u",
            "far = line.position[:2] - s * half * u",
            *push_lines(obj, ["entry", "far"])])
