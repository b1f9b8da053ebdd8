"""The methods a benchmark compares: VoxPoser and the "LLM + Primitives" baseline (App. A.4).

A :class:`Method` runs an instruction in a world with a backend, and knows how to build the
replay backend of a task's reference programs. ``get_method(name)`` lists the known methods.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Final

from voxposer.bench.task import BenchTask, EpisodeSetup
from voxposer.errors import ConfigError
from voxposer.lmp.backends.base import LLMBackend
from voxposer.lmp.backends.replay import ReplayBackend


@dataclass(frozen=True)
class Method:
    """A method under evaluation.

    Attributes:
        name: "voxposer" or "llm_primitives".
        label: how reports name it.
        paper_column: the column of the paper's Table 4 it corresponds to.
    """

    name: str
    label: str
    paper_column: str

    def run(self, world: Any, backend: LLMBackend, setup: EpisodeSetup, max_time_s: float) -> None:
        """Carry out ``setup.instruction`` (raises VoxPoserError when the method fails)."""
        if self.name == "voxposer":
            from voxposer.control import ExecutorConfig
            from voxposer.control.world_executor import WorldExecutor
            from voxposer.lmp.runtime import LMPRuntime
            from voxposer.lmp.scene import WorldScene

            (rng,) = setup.rng.spawn(1)
            executor = WorldExecutor(world, rng, ExecutorConfig(max_time_s=max_time_s))
            LMPRuntime(WorldScene(world), backend, executor).run(setup.instruction)
        else:
            from voxposer.bench.primitives import PrimitivesRuntime

            PrimitivesRuntime(world, backend).run(setup.instruction)

    def reference_backend(self, task: BenchTask, attrs: dict[str, str]) -> LLMBackend:
        """A replay backend serving the task's reference programs for ``attrs``."""
        progs = task.reference(attrs) if self.name == "voxposer" else \
            task.primitives_reference(attrs)
        if progs is None:
            raise ConfigError(f"task {task.name!r} has no reference programs for {self.name}")
        return ReplayBackend(progs.entries(), model="reference-programs")


#: method name → method.
METHODS: Final[dict[str, Method]] = {
    m.name: m
    for m in (
        Method("voxposer", "VoxPoser", "VoxPoser"),
        Method("llm_primitives", "LLM + Primitives", "LLM + Prim."),
    )
}


def get_method(name: str) -> Method:
    """The method called ``name``; raises ConfigError listing the known methods."""
    if name not in METHODS:
        raise ConfigError(f"unknown method {name!r}; methods are: {', '.join(METHODS)}")
    return METHODS[name]
