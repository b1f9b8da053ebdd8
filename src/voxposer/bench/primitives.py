"""The "LLM + Primitives" baseline (paper App. A.4): one LMP writing code against primitives.

A variant of Code as Policies: the same LLM, one few-shot prompt (``prompts/llm_primitives.txt``,
the size of VoxPoser's composer prompt) and the primitives ``move_to_pos``, ``rotate_by_quat``,
``set_vel``, ``open_gripper``, ``close_gripper`` plus ``detect`` — positions in metres, no value
maps, no planner. It reuses the LMP runtime (prompting, sandbox, self-correction, transcript):
:class:`PrimitivesRuntime` only adds the LMP spec and its variables.
"""

from __future__ import annotations

from typing import Any, Final, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from voxposer.errors import InvalidActionError, MoveMissedError
from voxposer.lmp.backends.base import LLMBackend
from voxposer.lmp.handoff import RecordingHandler
from voxposer.lmp.registry import LMPConfig, LMPSpec
from voxposer.lmp.runtime import LMPRuntime
from voxposer.lmp.sandbox import suspend_time_limit
from voxposer.lmp.scene import RobotScene
from voxposer.perception.perceiver import Perceiver
from voxposer.robot import Robot

#: The baseline's LMP: a composer-like program acting through primitive calls.
PRIMITIVES_SPEC: Final = LMPSpec("llm_primitives", "composer", with_objects=True)


class PrimitiveObject(NamedTuple):
    """What ``detect`` returns to baseline code: ``position`` (3,) and ``aabb`` (2, 3) [m]."""

    name: str
    position: NDArray[np.float64]
    aabb: NDArray[np.float64]


class Primitives:
    """The primitives, bound to a robot and its perceiver. Each motion waits until the robot
    arrives.

    Args:
        robot: the arm (:class:`voxposer.robot.Robot`).
        perceiver: what ``detect`` asks (:class:`voxposer.perception.Perceiver`).
        max_speed_scale: the largest ``set_vel`` scale the robot accepts.
    """

    def __init__(self, robot: Robot, perceiver: Perceiver, max_speed_scale: float = 5.0) -> None:
        self.robot = robot
        self.perceiver = perceiver
        self.max_speed_scale = float(max_speed_scale)
        self.speed = 1.0
        self.calls = 0

    def detect(self, name: str) -> PrimitiveObject:
        """The object called ``name`` as currently observed (metres)."""
        from voxposer.perception.names import match_name

        canonical = match_name(str(name), self.perceiver.object_names)
        det = self.perceiver.detect(canonical)
        return PrimitiveObject(canonical, np.asarray(det["position"], float).copy(),
                               np.asarray(det["aabb"], float).copy())

    def move_to_pos(self, pos: ArrayLike) -> None:
        """Move the end effector to ``pos`` [m], shape (3,), keeping its orientation."""
        p = np.asarray(pos, dtype=float).reshape(-1)
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise InvalidActionError(f"move_to_pos needs a finite (x, y, z) in metres; got {pos!r}")
        self._move(p, None)

    def rotate_by_quat(self, quat: ArrayLike) -> None:
        """Rotate the end effector by ``quat`` (x, y, z, w) in the world frame, in place."""
        q = np.asarray(quat, dtype=float).reshape(-1)
        if q.shape != (4,) or not np.all(np.isfinite(q)) or np.linalg.norm(q) < 1e-6:
            raise InvalidActionError(f"rotate_by_quat needs a quaternion (x, y, z, w); got {quat!r}")
        pos, current = self.robot.get_ee_pose()
        target = (Rotation.from_quat(q / np.linalg.norm(q)) * Rotation.from_quat(current)).as_quat()
        self._move(pos, target)

    def set_vel(self, scale: float) -> None:
        """Speed scale of the following motions (1 = the controller's default speed)."""
        s = float(scale)
        limit = self.max_speed_scale
        if not 0.01 <= s <= limit:
            raise InvalidActionError(f"set_vel scale must be in [0.01, {limit}]; got {scale!r}")
        self.speed = s

    def open_gripper(self) -> None:
        """Open the fingers."""
        self._act(self.robot.open_gripper)

    def close_gripper(self) -> None:
        """Close the fingers."""
        self._act(self.robot.close_gripper)

    def _act(self, fn: Any) -> Any:
        self.calls += 1
        with suspend_time_limit():
            return fn()

    def _move(self, position: NDArray[np.float64], quat: Any) -> None:
        """Move the end effector; a move that ends away from its target raises
        :class:`MoveMissedError` (the program sees it, and so does the episode record)."""
        result = self._act(lambda: self.robot.move_to_pose(position, quat,
                                                           speed_scale=self.speed))
        if not result.reached:
            raise MoveMissedError(np.round(position, 3).tolist(), result.position_error,
                                  result.rotation_error)

    def namespace(self) -> dict[str, Any]:
        """Names the baseline's code sees."""
        return {"detect": self.detect, "move_to_pos": self.move_to_pos,
                "rotate_by_quat": self.rotate_by_quat, "set_vel": self.set_vel,
                "open_gripper": self.open_gripper, "close_gripper": self.close_gripper}


class PrimitivesRuntime(LMPRuntime):
    """The LMP runtime with one extra LMP, ``llm_primitives``, whose code calls primitives.

    Args:
        body: the robot and its perceiver (:class:`voxposer.pipeline.Embodiment`).
        backend: the language model (the same one VoxPoser uses).
        config: retries, decoding and sandbox limits; ``config.held_out_task`` removes that
            task's few-shot examples from the ``llm_primitives`` prompt too (unseen
            instructions; the runtime's ``prompt`` loads every prompt with it).
    """

    def __init__(self, body: Any, backend: LLMBackend, config: LMPConfig | None = None, *,
                 max_speed_scale: float = 5.0, **kwargs: Any) -> None:
        super().__init__(RobotScene(body.perceiver, body.robot), backend, RecordingHandler(),
                         config, **kwargs)
        self.primitives = Primitives(body.robot, body.perceiver, max_speed_scale)
        if self.config.held_out_task is not None:  # the fold of its own prompt fails now
            self.prompt(PRIMITIVES_SPEC.name)

    def run(self, instruction: str) -> None:
        """Have the LLM write primitive code for ``instruction`` and run it (self-correcting
        until the code has moved the robot; then errors propagate)."""
        self._generate(PRIMITIVES_SPEC, instruction)

    def _variables(self, spec: LMPSpec, query: str) -> dict[str, Any]:
        if spec.name != PRIMITIVES_SPEC.name:
            return super()._variables(spec, query)
        calls_before = self.primitives.calls
        out: dict[str, Any] = {}
        for name, fn in self.primitives.namespace().items():
            out[name] = self._counting(fn, calls_before)
        out["objects"] = list(self.scene.object_names)
        return out

    def _counting(self, fn: Any, calls_before: int) -> Any:
        def call(*args: Any, **kwargs: Any) -> Any:
            result = fn(*args, **kwargs)
            if self.primitives.calls > calls_before:
                self._side_effects += 1  # the robot moved: do not retry this code
            return result
        call.__name__ = fn.__name__
        return call
