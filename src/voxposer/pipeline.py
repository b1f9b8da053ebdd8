"""The pipeline of the paper's Figure 2, wired once: perception and a robot feed the language
model programs, whose ``execute`` calls run in closed loop.

``voxposer run`` and ``voxposer bench`` both build their runs here, so they cannot drift apart.
An :class:`Embodiment` is what the pipeline acts through: a robot and a perceiver (in
simulation the MuJoCo world is the robot and the source of observations, and a ground-truth
segmentation perceiver reads them; a real arm with cameras is another embodiment).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from voxposer.control.config import ExecutorConfig
from voxposer.control.execution_result import ExecutionResult
from voxposer.control.robot_handoff import RobotHandoff
from voxposer.lmp.backends.base import LLMBackend
from voxposer.lmp.registry import LMPConfig
from voxposer.lmp.runtime import LMPRuntime
from voxposer.lmp.scene import RobotScene
from voxposer.lmp.transcript import Transcript
from voxposer.perception.perceiver import Perceiver
from voxposer.perception.segmentation import SegmentationPerceiver
from voxposer.robot import Robot


@dataclass(frozen=True)
class Embodiment:
    """A robot and the perception of its scene.

    Attributes:
        robot: the arm (:class:`voxposer.robot.Robot`).
        perceiver: objects, obstacles and sliding directions
            (:class:`voxposer.perception.Perceiver`).
    """

    robot: Robot
    perceiver: Perceiver

    @classmethod
    def simulated(cls, world: Any) -> Embodiment:
        """The MuJoCo world as robot, read by ground-truth segmentation (paper App. A.5)."""
        return cls(world, SegmentationPerceiver(world, world.grid))

    @property
    def scene(self) -> RobotScene:
        """What the language model programs perceive of it."""
        return RobotScene(self.perceiver, self.robot)


def voxposer_runtime(
    body: Embodiment, backend: LLMBackend, rng: np.random.Generator, *,
    executor_config: ExecutorConfig | None = None, lmp_config: LMPConfig | None = None,
    picture_dir: Path | None = None,
    on_replan: Callable[[ExecutionResult, Any], None] | None = None,
    transcript: Transcript | None = None,
) -> tuple[LMPRuntime, RobotHandoff]:
    """The LMP runtime whose ``execute`` calls the closed-loop executor on ``body``.

    Args:
        body: robot and perceiver.
        backend: the language model.
        rng: randomness of the pushing MPC.
        executor_config: closed-loop parameters (paper defaults when None).
        lmp_config: retries, decoding, sandbox limits, a held-out task's fold.
        picture_dir: where each sub-task's HTML picture goes (None: none).
        on_replan: called after every replan (live progress, disturbances).
        transcript: where every LLM call, program and execution is logged.

    Returns:
        (runtime, hand-off): run instructions with ``runtime.run``; ``handoff.records`` holds
        every executed sub-task.
    """
    handoff = RobotHandoff(body.robot, body.perceiver, rng, executor_config or ExecutorConfig(),
                           picture_dir=picture_dir, on_replan=on_replan)
    runtime = LMPRuntime(body.scene, backend, handoff, lmp_config, transcript=transcript)
    return runtime, handoff


__all__ = ["Embodiment", "voxposer_runtime"]
