"""Language model programs (paper Sec. 3.2 and 4): prompts, sandbox, runtime, transcript.

Public API:

* :class:`LMPRuntime` — runs the LMPs (planner, composer, parse_query_obj, get_*_map) of one
  scene and backend, with self-correction and a code cache; :class:`LMPConfig`, :data:`LMP_SPECS`.
* :class:`ValueMapProgram` / :class:`ObjectProgram` — re-evaluable results handed to ``execute``.
* :class:`ExecuteHandler`, :class:`ExecutionRequest`, :class:`RecordingHandler` — the ``execute`` hook.
* :class:`Scene`, :class:`BoxScene`, :class:`RobotScene`, :func:`make_tabletop_scene`.
* :class:`Sandbox`, :class:`SandboxConfig` — running untrusted generated code.
* :class:`Transcript` — JSONL log of prompts, responses, code and errors.
"""

from voxposer.lmp.api import LMPAPI
from voxposer.lmp.handoff import ExecuteHandler, ExecutionRequest, RecordingHandler
from voxposer.lmp.object_view import ObjectView
from voxposer.lmp.program import ObjectProgram, ValueMapProgram
from voxposer.lmp.registry import LMP_SPECS, MAP_LMPS, LMPConfig, LMPSpec
from voxposer.lmp.runtime import LMPRuntime
from voxposer.lmp.sandbox import Sandbox, SandboxConfig
from voxposer.lmp.scene import BoxScene, RobotScene, Scene, make_tabletop_scene
from voxposer.lmp.transcript import Transcript

__all__ = [
    "LMPAPI",
    "LMP_SPECS",
    "MAP_LMPS",
    "BoxScene",
    "ExecuteHandler",
    "ExecutionRequest",
    "LMPConfig",
    "LMPRuntime",
    "LMPSpec",
    "ObjectProgram",
    "ObjectView",
    "RecordingHandler",
    "RobotScene",
    "Sandbox",
    "SandboxConfig",
    "Scene",
    "Transcript",
    "ValueMapProgram",
    "make_tabletop_scene",
]
