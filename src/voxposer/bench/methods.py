"""The methods a benchmark compares: VoxPoser, the "LLM + Primitives" baseline (App. A.4) and
the "U-Net + MP" baseline (:mod:`voxposer.bench.unet_method`; no LLM, a trained checkpoint).

A :class:`Method` runs an instruction in a world with a backend, and knows how to build the
replay backend of a task's reference programs (and of their constraint-blind control).
``get_method(name)`` lists the known methods.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from voxposer.bench.intent_reference import with_expectation
from voxposer.bench.task import BenchTask, EpisodeSetup
from voxposer.bench.unet_method import NO_LLM, UNET_MP
from voxposer.errors import ConfigError
from voxposer.lmp.backends.base import LLMBackend
from voxposer.lmp.backends.replay import ReplayBackend

if TYPE_CHECKING:
    from voxposer.control.disturbance_schedule import Disturber
    from voxposer.planning.dynamics import DynamicsModel

#: builds an episode's disturber from (its generator, the reach tolerance [m]).
DisturberFactory = Callable[[np.random.Generator, float], "Disturber"]

#: ``--llm`` value of the hand-written reference programs (no LLM).
REFERENCE: Final = "reference"
#: ``--llm`` value of the reference programs minus the constraint's map (no LLM).
REFERENCE_BLIND: Final = "reference-blind"
#: the ``--llm`` values served by replayed hand-written programs rather than a model.
REFERENCE_LLMS: Final = (REFERENCE, REFERENCE_BLIND)
#: the ``llm`` values whose episodes need no LLM backend.
BACKENDLESS_LLMS: Final = (*REFERENCE_LLMS, NO_LLM)


@dataclass(frozen=True)
class Method:
    """A method under evaluation.

    Attributes:
        name: "voxposer", "llm_primitives" or "unet_mp".
        label: how reports name it.
        paper_column: the column of the paper's Table 4 it corresponds to.
    """

    name: str
    label: str
    paper_column: str

    def run(self, world: Any, backend: LLMBackend, setup: EpisodeSetup, max_time_s: float,
            instructions: str = "seen", make_disturber: DisturberFactory | None = None,
            intents: list[dict[str, Any]] | None = None, checkpoint: str | None = None,
            perception: str | None = None, push_model: DynamicsModel | None = None) -> None:
        """Carry out ``setup.instruction`` (raises VoxPoserError when the method fails).

        Args:
            max_time_s: simulated time limit of each ``execute`` call [s].
            instructions: "unseen" holds the few-shot examples of ``setup.task`` out of every
                prompt (leave-one-task-out); "seen" keeps them.
            make_disturber: builds the episode's :class:`Disturber` from (a generator spawned
                from ``setup.rng``, the executor's reach tolerance [m]); None: undisturbed.
                VoxPoser is disturbed on sub-task progress (the executor's ``on_replan``), the
                baseline, which never replans, on the sim-time schedule
                (:mod:`voxposer.control.disturbance_schedule`).
            intents: receives the post-conditions VoxPoser's plan stated, evaluated
                (:class:`voxposer.lmp.intent.IntentResult` as dicts), also when the run fails.
            checkpoint: the trained model's path (unet_mp: its U-Net checkpoint).
            perception: how the robot finds objects (:data:`voxposer.pipeline.PERCEPTIONS`;
                None: this process's default).
            push_model: the pushing MPC's dynamics model (None: the paper's heuristic); one
                with a ``push_samples`` attribute sets how many pushes the MPC samples.
        """
        from voxposer.control import ExecutorConfig
        from voxposer.lmp.registry import LMPConfig

        config = LMPConfig(held_out_task=setup.task) if instructions == "unseen" else None
        exec_config = ExecutorConfig(max_time_s=max_time_s)
        samples = getattr(push_model, "push_samples", None)
        if samples is not None:  # an expensive model (the simulator) is sampled less
            exec_config = replace(exec_config, push=replace(exec_config.push, n_samples=samples))
        # the executor's generator is the first child with or without a disturber
        rng, disturb_rng = setup.rng.spawn(2)
        disturber = None if make_disturber is None else make_disturber(
            disturb_rng, exec_config.reach_tolerance_m)
        from voxposer.pipeline import Embodiment, voxposer_runtime

        if self.name == UNET_MP:
            from voxposer.bench.unet_method import run_unet_mp

            run_unet_mp(world, setup, checkpoint, exec_config, rng,
                        None if disturber is None else disturber.on_replan,
                        push_model=push_model)
            return
        body = Embodiment.simulated(world, perception)
        if self.name == "voxposer":
            runtime, _ = voxposer_runtime(
                body, backend, rng, executor_config=exec_config, lmp_config=config,
                on_replan=None if disturber is None else disturber.on_replan,
                push_model=push_model)
            try:
                runtime.run(setup.instruction)
            finally:
                if intents is not None:
                    intents.extend(r.to_json() for r in runtime.intent.results)
        else:
            from voxposer.bench.primitives import PrimitivesRuntime

            runtime = PrimitivesRuntime(body, backend, config,
                                        max_speed_scale=world.config.controller.max_speed_scale)
            if disturber is None:
                runtime.run(setup.instruction)
            else:
                with disturber.attach():
                    runtime.run(setup.instruction)

    def reference_backend(self, task: BenchTask, attrs: dict[str, str], *,
                          blind: bool = False) -> LLMBackend:
        """A replay backend serving the task's reference programs for ``attrs`` (with
        ``blind``, its constraint-blind control: the reference minus the constraint's map)."""
        if self.name == UNET_MP:  # answers nothing: the method calls no LLM
            return ReplayBackend([], model="no LLM")
        if blind:
            if self.name != "voxposer":
                raise ConfigError(f"constraint-blind controls exist for voxposer only, not "
                                  f"{self.name!r}")
            progs = task.blind(attrs)
            if progs is None:
                raise ConfigError(f"task {task.name!r} carries no constraint, so it has no "
                                  "constraint-blind control")
            progs = with_expectation(progs, task.name, attrs)
            return ReplayBackend(progs.entries(), model="reference-blind-programs")
        progs = task.reference(attrs) if self.name == "voxposer" else \
            task.primitives_reference(attrs)
        if progs is None:
            raise ConfigError(f"task {task.name!r} has no reference programs for {self.name}")
        if self.name == "voxposer":
            progs = with_expectation(progs, task.name, attrs)
        return ReplayBackend(progs.entries(), model="reference-programs")


#: method name → method.
METHODS: Final[dict[str, Method]] = {
    m.name: m
    for m in (
        Method("voxposer", "VoxPoser", "VoxPoser"),
        Method("llm_primitives", "LLM + Primitives", "LLM + Prim."),
        Method(UNET_MP, "U-Net + MP", "U-Net + MP"),
    )
}


def get_method(name: str) -> Method:
    """The method called ``name``; raises ConfigError listing the known methods."""
    if name not in METHODS:
        raise ConfigError(f"unknown method {name!r}; methods are: {', '.join(METHODS)}")
    return METHODS[name]
