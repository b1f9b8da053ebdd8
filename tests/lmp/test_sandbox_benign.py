"""Real generated code still runs under the sandbox's limits: every prompt example and recording.

The allowlist, the size/work limits and the voxel-index rule must refuse attacks without
refusing what the prompts teach and the models answer. Each program runs in the sandbox with
the scene-bound API of the tabletop scene; LMP calls, ``execute`` and the motion primitives are
stubs (they run elsewhere).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import pytest

from voxposer.errors import SandboxError
from voxposer.lmp import LMP_SPECS, make_tabletop_scene
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.codetext import extract_code
from voxposer.lmp.intent import IntentChecks
from voxposer.lmp.prompt import load_prompt
from voxposer.lmp.sandbox import Sandbox, SandboxConfig

TESTS = Path(__file__).parents[1]
RECORDINGS = [TESTS / "lmp" / "recordings" / "closed_loop.jsonl",
              TESTS / "lmp" / "recordings" / "self_correction.jsonl",
              TESTS / "control" / "recordings" / "tabletop.jsonl"]
MAP_LMPS = ("get_affordance_map", "get_avoidance_map", "get_rotation_map", "get_velocity_map",
            "get_gripper_map")


@pytest.fixture(scope="module")
def api() -> LMPAPI:
    return LMPAPI(make_tabletop_scene())


@pytest.fixture(scope="module", params=["inline", "process"])
def sandbox(request: pytest.FixtureRequest) -> Sandbox:
    """Both isolation modes must run every example and recording alike."""
    sandbox = Sandbox(SandboxConfig(isolation=request.param))
    yield sandbox
    sandbox.close()


class MetricObject(NamedTuple):
    """What the LLM + primitives baseline's ``detect`` returns (a NamedTuple, in metres)."""

    name: str
    position: np.ndarray
    aabb: np.ndarray


def _namespace(api: LMPAPI, lmp: str = "") -> dict[str, Any]:
    """The API plus stubs for what runs outside the program (LMPs, execution, primitives)."""
    calls: list[str] = []

    def stub(name: str) -> Callable[..., Any]:
        def call(*args: Any, **kwargs: Any) -> Callable[[], None]:
            calls.append(name)
            return lambda: None
        return call

    out: dict[str, Any] = dict(api.namespace())
    out["parse_query_obj"] = api.detect
    out["objects"] = list(api.scene.object_names)
    for name in (*MAP_LMPS, "execute", "reset_to_default_pose", "composer", "move_to_pos",
                 "rotate_by_quat", "set_vel", "open_gripper", "close_gripper"):
        out[name] = stub(name)
    if lmp == "llm_primitives":
        def detect(name: str) -> MetricObject:
            obj = api.detect(name)
            return MetricObject(obj.name, obj.position_world.copy(), obj.aabb_world.copy())
        out["detect"] = detect
    return out


def _examples() -> list[tuple[str, int, str]]:
    return [(name, i, example.assistant) for name in LMP_SPECS
            for i, example in enumerate(load_prompt(name).examples)]


@pytest.mark.parametrize("lmp, index, code", _examples(),
                         ids=[f"{n}-{i}" for n, i, _ in _examples()])
def test_every_prompt_example_runs(sandbox: Sandbox, api: LMPAPI, lmp: str, index: int,
                                   code: str) -> None:
    namespace = _namespace(api, lmp)
    intent = IntentChecks(api)
    intent.ee_speed = 0.25  # [m/s]: speed(...) conditions are evaluated (no path: not held)
    if lmp == "planner":  # the post-condition helpers, evaluated on the fixed scene
        namespace.update(intent.namespace(lambda fn: fn))
    out = sandbox.run(extract_code(code), namespace)
    if lmp in MAP_LMPS:
        value = out["ret_val"]
        assert isinstance(value, np.ndarray) and value.shape[:3] == api.grid.shape
    # every post-condition an example states is one the helpers can evaluate
    assert not [r for r in intent.results if r.error], intent.results


def _recorded() -> list[tuple[str, str, str]]:
    out = []
    for path in RECORDINGS:
        for line in path.read_text().splitlines():
            if line.strip() and not line.startswith("//"):
                entry = json.loads(line)
                out += [(path.name, entry["lmp"], text) for text in entry["responses"]]
    return out


@pytest.mark.parametrize("source, lmp, text", _recorded(),
                         ids=[f"{s}-{lmp}-{i}" for i, (s, lmp, _) in enumerate(_recorded())])
def test_recorded_programs_are_not_refused(sandbox: Sandbox, api: LMPAPI, source: str, lmp: str,
                                           text: str) -> None:
    """Recordings hold deliberate mistakes (for self-correction); only ``import`` is refused."""
    code = extract_code(text)
    try:
        sandbox.run(code, _namespace(api))
    except SandboxError as exc:
        assert "import" in code, f"{type(exc).__name__}: {exc}"
        assert "import" in str(exc)
    except (SyntaxError, IndexError, KeyError, ValueError):
        pass  # the recorded mistakes (unknown objects, a 4-D index, an unclosed call)
