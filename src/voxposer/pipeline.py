"""The pipeline of the paper's Figure 2, wired once: perception and a robot feed the language
model programs, whose ``execute`` calls run in closed loop.

``voxposer run`` and ``voxposer bench`` both build their runs here, so they cannot drift apart.
An :class:`Embodiment` is what the pipeline acts through: a robot and a perceiver (in
simulation the MuJoCo world is the robot and the source of observations, and a ground-truth
segmentation perceiver, or a colour-depth one reading pixels only, reads them; a real arm with
cameras is another embodiment).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Final

import numpy as np

from voxposer.control.config import ExecutorConfig
from voxposer.control.execution_result import ExecutionResult
from voxposer.control.robot_handoff import RobotHandoff
from voxposer.errors import ConfigError
from voxposer.lmp.backends.base import LLMBackend
from voxposer.lmp.registry import LMPConfig
from voxposer.lmp.runtime import LMPRuntime
from voxposer.lmp.scene import RobotScene
from voxposer.lmp.transcript import Transcript
from voxposer.perception.colour_depth import ColourDepthPerceiver
from voxposer.perception.label_tracking import LabelTrackingConfig
from voxposer.perception.noisy_source import NoisyObservationSource, seed_from_scene
from voxposer.perception.perceiver import Perceiver
from voxposer.perception.segmentation import SegmentationPerceiver
from voxposer.perception.sensor_noise import SensorNoiseConfig
from voxposer.perception.view_registration import RegisteredObservationSource
from voxposer.planning.dynamics import DynamicsModel
from voxposer.robot import Robot

#: How a simulated embodiment finds objects (``--perception``): the simulator's ground-truth
#: segmentation channel, or colour and depth pixels only
#: (:class:`~voxposer.perception.colour_depth.ColourDepthPerceiver`); "-noisy": the same on
#: views with a consumer RGB-D camera's errors (:mod:`voxposer.perception.sensor_noise`; for
#: ground truth, corrupted masks too); "colour-depth-tracked": the pixel perception carrying
#: its labels between detections (:mod:`voxposer.perception.label_tracking`, its defaults).
PERCEPTIONS: Final = ("ground-truth", "colour-depth", "ground-truth-noisy", "colour-depth-noisy",
                      "colour-depth-tracked", "colour-depth-tracked-noisy")
#: the perceptions that carry labels between detections.
_TRACKED: Final = ("colour-depth-tracked", "colour-depth-tracked-noisy")
_perception = {"default": "ground-truth"}


def check_perception(name: str) -> str:
    """``name`` if it is one of :data:`PERCEPTIONS`; else ConfigError listing them."""
    if name not in PERCEPTIONS:
        raise ConfigError(f"unknown perception {name!r}; choose one of: {', '.join(PERCEPTIONS)}")
    return name


def use_perception(name: str) -> None:
    """Make ``name`` (:data:`PERCEPTIONS`) what :meth:`Embodiment.simulated` uses when not told
    otherwise, in this process (a benchmark worker sets it once, before its episodes)."""
    _perception["default"] = check_perception(name)


def simulated_perceiver(world: Any, perception: str, *, noise: SensorNoiseConfig | None = None,
                        seed: int | None = None, register: bool = True,
                        tracking: LabelTrackingConfig | None = None) -> Perceiver:
    """The perceiver ``perception`` (:data:`PERCEPTIONS`) reading ``world``'s cameras.

    A "-noisy" one reads them through a
    :class:`~voxposer.perception.noisy_source.NoisyObservationSource` with ``noise`` (None:
    the typical defaults of :class:`SensorNoiseConfig`; the label channel is left alone for
    colour-depth, which never reads it), seeded with ``seed`` (None: from the world's scene,
    so an episode's noise is fixed by its scene), and, with ``register`` and calibration
    error on, registers those cameras against each other once per episode
    (:class:`~voxposer.perception.view_registration.RegisteredObservationSource`).
    ``tracking``: carry the pixel labels between detections
    (:mod:`voxposer.perception.label_tracking`; colour-depth perceptions only; None: its
    defaults for the "-tracked" perceptions, none for the others).

    Raises:
        ConfigError: an unknown perception, or ``tracking`` for one that does not detect from
            pixels.
    """
    check_perception(perception)
    if tracking is None and perception in _TRACKED:
        tracking = LabelTrackingConfig()
    if tracking is not None and not perception.startswith("colour-depth"):
        raise ConfigError(f"label tracking is for the colour-depth perceptions (they detect from "
                          f"pixels); perception {perception!r} reads the simulator's labels")
    source = world
    if perception.endswith("-noisy"):
        config = noise or SensorNoiseConfig()
        if perception.startswith("colour-depth"):
            config = replace(config, mask_corruption=False)
        seed = seed_from_scene(getattr(world, "placement", None)) if seed is None else seed
        source = NoisyObservationSource(world, config, seed)
        if register and config.calibration:
            source = RegisteredObservationSource(source, world.grid)
    if perception.startswith("colour-depth"):
        return ColourDepthPerceiver(source, world.grid, tracking)
    return SegmentationPerceiver(source, world.grid)


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
    def simulated(cls, world: Any, perception: str | None = None, *,
                  tracking: LabelTrackingConfig | None = None) -> Embodiment:
        """The MuJoCo world as robot, read by ``perception`` (:data:`PERCEPTIONS`; None: this
        process's default, see :func:`use_perception`, normally "ground-truth": segmentation as
        in the paper's App. A.5); ``tracking`` as :func:`simulated_perceiver`."""
        return cls(world, simulated_perceiver(world, perception or _perception["default"],
                                              tracking=tracking))

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
    push_model: DynamicsModel | None = None,
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
        push_model: the pushing MPC's dynamics model (None: the paper's heuristic,
            :class:`~voxposer.planning.dynamics.TranslationPush`).

    Returns:
        (runtime, hand-off): run instructions with ``runtime.run``; ``handoff.records`` holds
        every executed sub-task.
    """
    handoff = RobotHandoff(body.robot, body.perceiver, rng, executor_config or ExecutorConfig(),
                           picture_dir=picture_dir, on_replan=on_replan, push_model=push_model)
    runtime = LMPRuntime(body.scene, backend, handoff, lmp_config, transcript=transcript)
    runtime.intent.ee_speed = body.robot.ee_speed  # for the planner's speed(...) conditions
    return runtime, handoff


__all__ = ["PERCEPTIONS", "Embodiment", "check_perception", "simulated_perceiver",
           "use_perception", "voxposer_runtime"]
