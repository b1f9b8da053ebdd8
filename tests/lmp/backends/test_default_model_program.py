"""The bundled model in-process writes a value-map program that runs in the sandbox (slow)."""

from pathlib import Path

import numpy as np
import pytest

from voxposer.lmp.backends import LLMConfig, make_backend
from voxposer.lmp.runtime import LMPRuntime
from voxposer.lmp.scene import make_tabletop_scene


@pytest.mark.slow
def test_default_model_program_runs_in_the_sandbox(
    default_model_path: Path, tmp_path: Path
) -> None:
    scene = make_tabletop_scene()
    backend = make_backend(LLMConfig(cache=False))  # prefix states from setup's pre-warm
    try:
        runtime = LMPRuntime(scene, backend)
        value = runtime.query("get_affordance_map", "a point 10cm above the blue block")
    finally:
        backend.close()
    assert runtime.llm_calls >= 1
    executed = [e for e in runtime.transcript.events if e["event"] == "exec"]
    assert executed and executed[-1]["ok"]  # the accepted program ran in the sandbox
    target = np.argwhere(value == value.max())[0]
    blue = scene.detect("blue block")  # world coordinates [m]
    target_world = scene.grid.voxel_to_world(target)
    assert np.all(np.abs(target_world[:2] - blue.position[:2]) <= 0.02)
    assert 0.05 <= target_world[2] - blue.aabb[1][2] <= 0.15  # 10 cm above (its top or centre)
