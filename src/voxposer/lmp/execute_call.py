"""The ``execute(movable, **maps)`` that composer code calls, bound to one sub-task.

It turns the arguments into re-evaluable callables (:class:`ExecutionRequest`), refuses what
cannot run before anything moves (unknown map names; no affordance map; an entity that is its
own target:
:func:`~voxposer.lmp.checks.check_execute_target`), corrects an entity the sub-task's words
contradict (:func:`~voxposer.lmp.checks.corrected_movable`, a ``movable_corrected`` transcript
event), hands the request to the execute handler,
and records the outcome in the transcript and for the intent checks. A failure of the handler
is wrapped in :class:`~voxposer.lmp.runtime_errors.NoRetry`: it already had side effects.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

from voxposer.errors import ConfigError, ResultError, pending_interrupt
from voxposer.lmp.checks import check_execute_target, corrected_movable
from voxposer.lmp.handoff import MAP_ARGUMENTS, ExecuteHandler, ExecutionRequest
from voxposer.lmp.intent import IntentChecks
from voxposer.lmp.object_view import ObjectView
from voxposer.lmp.runtime_errors import NoRetry
from voxposer.lmp.sandbox import suspend_time_limit
from voxposer.lmp.transcript import Transcript


class ExecuteCall:
    """``execute`` of the composer code for ``subtask``.

    Args:
        subtask: the composer's query.
        handler: receives the request (the robot, or a recorder in tests).
        program: ``(lmp, query)`` → a re-evaluable program (for a movable given by name).
        transcript: where each call's outcome is written.
        intent: told of every executed outcome (paths for ``away``).
        on_effect: called once the request is about to reach the handler (a side effect).
        objects: the scene's object names (a pushed object is one of them).
    """

    def __init__(self, subtask: str, handler: ExecuteHandler, program: Callable[[str, str], Any],
                 transcript: Transcript, intent: IntentChecks,
                 on_effect: Callable[[], None], objects: tuple[str, ...] = ()) -> None:
        self.subtask = subtask
        self.handler = handler
        self.program = program
        self.transcript = transcript
        self.intent = intent
        self.on_effect = on_effect
        self.objects = tuple(objects)
        self.__name__ = "execute"

    def __call__(self, movable: Any, **maps: Any) -> None:
        unknown = sorted(set(maps) - set(MAP_ARGUMENTS))
        if unknown:
            raise TypeError(f"execute() got unknown argument(s) {unknown}; it accepts "
                            f"movable and {', '.join(MAP_ARGUMENTS)}")
        request = ExecutionRequest(
            subtask=self.subtask, movable=self._as_callable(movable, "parse_query_obj"),
            maps={k: self._as_callable(v, k) for k, v in maps.items() if v is not None})
        affordance = request.maps.get("affordance_map")
        if affordance is None:  # before any side effect: the model may still fix it
            raise ResultError(
                "execute() needs an affordance_map: nothing says where to go. Every motion has "
                "a target, also 'move away from X' (a point some cm beyond X) or 'release' "
                "(the gripper's own position)")
        with suspend_time_limit():
            entity = request.movable()
            if (fix := corrected_movable(self.subtask, entity, self.objects)) is not None:
                request = replace(request, movable=self.program("parse_query_obj", fix[0]))
                self.transcript.write("movable_corrected", subtask=self.subtask,
                                      movable=str(getattr(entity, "name", "")), to=fix[0],
                                      why=fix[1])
                entity = request.movable()
            check_execute_target(entity, affordance())
        self.on_effect()
        with suspend_time_limit():
            try:
                outcome = self.handler.execute(request)
            except Exception as exc:
                if (stop := pending_interrupt(exc)) is not None:
                    raise stop from None
                self.transcript.write("execute", subtask=self.subtask, success=False,
                                      message=f"{type(exc).__name__}: {exc}")
                raise NoRetry(exc) from exc
        self.intent.add_execution(outcome)
        self.transcript.write("execute", subtask=self.subtask,
                              success=bool(getattr(outcome, "success", True)),
                              message=str(getattr(outcome, "message", "")))

    def _as_callable(self, value: Any, what: str) -> Any:
        if callable(value):
            return value
        if isinstance(value, str) and what == "parse_query_obj":
            return self.program("parse_query_obj", value)
        if isinstance(value, ObjectView) or hasattr(value, "shape"):
            return lambda: value
        raise ConfigError(f"execute() needs {what} from an LMP call (or an array); got "
                          f"{type(value).__name__}")
