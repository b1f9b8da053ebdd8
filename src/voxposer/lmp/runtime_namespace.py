"""The names a language model program's code sees, by its role (paper Sec. 3.2, Code as Policies).

A mixin of :class:`~voxposer.lmp.runtime.LMPRuntime`: map programs get ``parse_query_obj`` (run
at once), composer programs every map LMP (as re-evaluable programs) and ``execute``, the
planner ``composer`` and the intent checks. Each LMP callable runs outside the sandbox's time
limit: it is trusted code that may perceive or ask the model.
"""

from __future__ import annotations

from typing import Any

from voxposer.lmp.api import LMPAPI
from voxposer.lmp.execute_call import ExecuteCall
from voxposer.lmp.handoff import ExecuteHandler
from voxposer.lmp.intent import IntentChecks
from voxposer.lmp.program import ValueMapProgram
from voxposer.lmp.query_forms import QueryForms
from voxposer.lmp.registry import MAP_LMPS, LMPSpec
from voxposer.lmp.runtime_errors import NoRetry
from voxposer.lmp.sandbox import suspend_time_limit
from voxposer.lmp.scene import Scene
from voxposer.lmp.transcript import Transcript


class ProgramNamespaces:
    """The variable context of each LMP role (needs the attributes and methods declared below)."""

    scene: Scene
    api: LMPAPI
    intent: IntentChecks
    forms: QueryForms
    handler: ExecuteHandler
    transcript: Transcript
    _side_effects: int
    _subtask: str

    def query(self, lmp: str, query: str) -> Any:
        raise NotImplementedError

    def program(self, lmp: str, query: str) -> ValueMapProgram:
        raise NotImplementedError

    def _variables(self, spec: LMPSpec, query: str) -> dict[str, Any]:
        """The names ``spec``'s code sees (shared API + LMP callables for its role)."""
        out: dict[str, Any] = dict(self.api.namespace())
        if spec.role == "map":
            out["parse_query_obj"] = self._eager("parse_query_obj", context=query)
        elif spec.role == "composer":
            for name in ("parse_query_obj", *MAP_LMPS):
                out[name] = self._lazy(name, context=query)
            out["execute"] = ExecuteCall(query, self.handler, self.program, self.transcript,
                                         self.intent, self._count_effect,
                                         tuple(self.scene.object_names))
            out["reset_to_default_pose"] = self._reset
        elif spec.role == "planner":
            out = {"composer": self._composer, "reset_to_default_pose": self._reset,
                   **self.intent.namespace(_untimed)}
        if spec.with_objects:
            out["objects"] = list(self.scene.object_names)
        return out

    def _eager(self, lmp: str, context: str = "") -> Any:
        def call(query: str) -> Any:
            with suspend_time_limit():
                return self.query(lmp, self.forms.rewritten(lmp, str(query), context))
        call.__name__ = lmp
        return call

    def _lazy(self, lmp: str, context: str = "") -> Any:
        def call(query: str) -> ValueMapProgram:
            with suspend_time_limit():
                return self.program(lmp, self.forms.rewritten(lmp, str(query), context))
        call.__name__ = lmp
        return call

    def _composer(self, subtask: str) -> None:
        self._side_effects += 1
        with suspend_time_limit():
            self.intent.begin_subtask(str(subtask))
            previous, self._subtask = self._subtask, str(subtask)
            try:
                self.query("composer", str(subtask))
            finally:
                self._subtask = previous

    def _reset(self) -> None:
        self._side_effects += 1
        with suspend_time_limit():
            try:
                self.handler.reset_to_default_pose()
            except Exception as exc:
                raise NoRetry(exc) from exc

    def _count_effect(self) -> None:
        self._side_effects += 1


def _untimed(fn: Any) -> Any:
    """``fn`` run outside the sandbox's time limit (trusted code that perceives)."""
    def call(*args: Any, **kwargs: Any) -> Any:
        with suspend_time_limit():
            return fn(*args, **kwargs)
    call.__name__ = getattr(fn, "__name__", "helper")
    return call
