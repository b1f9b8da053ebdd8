"""Runs the language model programs: prompting, sandboxed execution, self-correction, caching.

One :class:`LMPRuntime` holds the shared variable context (the scene-bound API, every LMP as a
callable, ``execute``), the code cache keyed by (LMP, query), and the transcript. LMPs call each
other through their code, as in Code as Policies: ``get_affordance_map`` code calls
``parse_query_obj('blue block')``, which runs that LMP (asking the LLM only the first time).

Self-correction: when code raises, leaves its result unset, or fails a sanity check
(:mod:`voxposer.lmp.checks`), the error is appended to the conversation and the model is asked
again, up to ``LMPConfig.max_attempts`` calls. Code that has already had side effects (an
``execute`` or ``composer`` call) is not retried.

An object the scene lacks: ``parse_query_obj`` code that finds nothing (``ret_val = None`` or an
empty list) fails with an :class:`~voxposer.errors.UnknownObjectError` naming the query and the
scene's objects, as ``detect`` of an unknown name does; that is what the model sees when it
retries. A second "nothing" after being shown the scene's objects settles it. An LMP that gives
up on an unknown object raises :class:`~voxposer.errors.UnresolvedObjectError`, which every
enclosing LMP passes on without retrying: the user sees the object, not a chain of failures.

With ``LMPConfig.held_out_task`` every prompt loses the examples tagged with that task (an
"unseen instruction" fold); a prompt the fold changed is sent under its own prefix id
(``"composer~push_to_pos"``), so a backend caches its prefix beside the default one.
"""

from __future__ import annotations

import logging
import time
from dataclasses import asdict
from functools import partial
from typing import Any

from voxposer.errors import (
    LLMError,
    LMPFailedError,
    ProgramError,
    UnresolvedObjectError,
    pending_interrupt,
)
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.backends.base import ChatMessage, LLMBackend, LLMRequest
from voxposer.lmp.checks import check_result
from voxposer.lmp.codetext import extract_code
from voxposer.lmp.handoff import ExecuteHandler, RecordingHandler
from voxposer.lmp.instruction_forms import planner_instruction
from voxposer.lmp.intent import IntentChecks
from voxposer.lmp.plan_pipeline import complete_plan
from voxposer.lmp.plan_review import PlanReview
from voxposer.lmp.prefetch import Prefetched, map_queries
from voxposer.lmp.program import ObjectProgram, ValueMapProgram
from voxposer.lmp.prompt import Prompt, load_prompt
from voxposer.lmp.query_forms import RETRY_MESSAGE, QueryForms, query_message
from voxposer.lmp.registry import LMP_SPECS, LMPConfig, LMPSpec, get_spec
from voxposer.lmp.runtime_errors import NoRetry, NothingFound, describe, give_up, is_nothing
from voxposer.lmp.runtime_namespace import ProgramNamespaces
from voxposer.lmp.sandbox import Sandbox
from voxposer.lmp.scene import Scene
from voxposer.lmp.transcript import Transcript

logger = logging.getLogger(__name__)

class LMPRuntime(ProgramNamespaces):
    """The LMPs of one scene and backend.

    Args:
        scene: what the programs perceive (:class:`~voxposer.lmp.scene.Scene`).
        backend: the language model.
        handler: receives ``execute`` calls (default: a :class:`RecordingHandler`).
        config: retries, decoding and sandbox limits.
        transcript: where to log prompts, responses, code and errors (default: in memory).

    Attributes:
        llm_calls: number of backend calls made so far.
        code_cache: (lmp, query) → accepted code.
    """

    def __init__(self, scene: Scene, backend: LLMBackend, handler: ExecuteHandler | None = None,
                 config: LMPConfig | None = None, transcript: Transcript | None = None) -> None:
        self.scene = scene
        self.backend = backend
        self.handler: ExecuteHandler = handler if handler is not None else RecordingHandler()
        self.config = config or LMPConfig()
        self.transcript = transcript or Transcript()
        self.api = LMPAPI(scene)
        self.intent = IntentChecks(self.api)
        self.forms = QueryForms(self.config, lambda: self.scene.object_names, self.transcript)
        self.sandbox = Sandbox(self.config.sandbox)
        self.llm_calls = 0
        self.code_cache: dict[tuple[str, str], str] = {}
        self._prompts: dict[str, Prompt] = {}
        self._prefetched = Prefetched()
        self._depth = 0
        self._side_effects = 0
        self._subtask = ""
        if self.config.held_out_task is not None:  # a fold that empties a prompt fails now
            for name in LMP_SPECS:
                self.prompt(name)

    # ------------------------------------------------------------------ public entry points
    def run(self, instruction: str) -> None:
        """Plan ``instruction`` into sub-tasks and carry each out (planner → composer → execute);
        the post-conditions the plan states are in ``intent.results`` (and the transcript)."""
        instruction = planner_instruction(instruction, self.scene, self.config, self.transcript)
        try:
            self.query("planner", instruction)
        finally:
            for result in self.intent.results:
                self.transcript.write("intent", **result.to_json())

    def query(self, lmp: str, query: str) -> Any:
        """The current result of ``lmp(query)``: cached code re-run, or generated (LLM) first."""
        if (lmp, query) in self.code_cache or self._resolved(lmp, query):
            return self.replay(lmp, query)
        return self._generate(get_spec(lmp), query)

    def _resolved(self, lmp: str, query: str) -> bool:
        """Whether ``lmp(query)`` is answered without the model and now cached
        (:meth:`QueryForms.exact_code`)."""
        if (code := self.forms.exact_code(lmp, query)) is None:
            return False
        self.code_cache[(lmp, query)] = code
        return True

    def program(self, lmp: str, query: str) -> ValueMapProgram:
        """A re-evaluable program for ``lmp(query)`` (generated and checked now if not cached)."""
        if (lmp, query) not in self.code_cache and not self._resolved(lmp, query):
            self._generate(get_spec(lmp), query)
        cls = ObjectProgram if get_spec(lmp).role == "object" else ValueMapProgram
        return cls(self, lmp, query, self.code_cache[(lmp, query)])

    def replay(self, lmp: str, query: str) -> Any:
        """Re-run the cached code of ``lmp(query)`` on the current scene (no LLM call)."""
        spec, code = get_spec(lmp), self.code_cache[(lmp, query)]
        try:
            return self._evaluate(spec, query, code, attempt=0, replay=True)
        except Exception as exc:
            if (stop := pending_interrupt(exc)) is not None:
                raise stop from None
            raise LMPFailedError(lmp, query, [{"code": code, "error": describe(exc)}]) from exc

    def prompt(self, lmp: str) -> Prompt:
        """The (cached) prompt of ``lmp``, without the examples of ``config.held_out_task``."""
        if lmp not in self._prompts:
            self._prompts[lmp] = load_prompt(lmp, self.config.prompt_dir,
                                             held_out_task=self.config.held_out_task)
        return self._prompts[lmp]

    # ------------------------------------------------------------------------ generation
    def _generate(self, spec: LMPSpec, query: str) -> Any:
        if self._depth >= self.config.max_depth:
            raise ProgramError(f"LMP calls nested deeper than {self.config.max_depth} "
                               f"({spec.name}({query!r})); do not call LMPs recursively")
        prompt = self.prompt(spec.name)
        base = self._first_messages(spec, query)
        n_prefix = prompt.n_prefix_messages
        self.transcript.prompt_once(spec.name, [asdict(m) for m in base[:n_prefix]])
        messages = list(base)
        attempts: list[dict[str, str]] = []
        last: BaseException | None = None
        review = PlanReview(query, self.config.max_attempts, clauses=self.config.clause_checklist,
                            post_conditions=self.config.intent_checklist) \
            if spec.name == "planner" and (self.config.clause_checklist
                                           or self.config.intent_checklist) else None
        self._depth += 1
        try:
            for attempt in range(1, self.config.max_attempts + 1):
                text = self._complete(spec, query, messages, n_prefix=n_prefix,
                                      attempt=attempt, n_context=len(base) - 1)
                code = extract_code(text)
                if review is not None:
                    code, gap_message, gaps = review.review(code, attempt)
                    if gaps:
                        self.transcript.write("checklist", query=query, attempt=attempt,
                                              gaps=[g.describe() for g in gaps])
                    if gap_message is not None:
                        messages += [ChatMessage("assistant", text),
                                     ChatMessage("user", RETRY_MESSAGE.format(error=gap_message))]
                        continue
                if spec.name == "planner":
                    code = self._complete_plan(query, code, attempt)
                elif spec.name == "composer" and self.config.batch_map_calls:
                    self._prefetch_maps(code)
                effects = self._side_effects
                try:
                    value = self._evaluate(spec, query, code, attempt=attempt, replay=False)
                except (UnresolvedObjectError, LLMError):
                    # an LMP this code called gave up on the object, or the model's endpoint
                    # failed: no retry here, the caller sees that error itself
                    raise
                except Exception as exc:
                    if (stop := pending_interrupt(exc)) is not None:
                        raise stop from None
                    attempts.append({"code": code, "error": describe(exc)})
                    cause = exc.original if isinstance(exc, NoRetry) else exc
                    settled = isinstance(cause, NothingFound) and isinstance(last, NothingFound)
                    last = cause
                    if self._side_effects != effects or isinstance(exc, NoRetry) or settled:
                        raise give_up(spec.name, query, attempts, cause) from cause
                    logger.info("%s(%r) attempt %d failed: %s", spec.name, query, attempt,
                                attempts[-1]["error"])
                    messages += [ChatMessage("assistant", text),
                                 ChatMessage("user", RETRY_MESSAGE.format(error=attempts[-1]["error"]))]
                    continue
                self.code_cache[(spec.name, query)] = code
                return value
        finally:
            self._depth -= 1
        raise give_up(spec.name, query, attempts, last) from last

    def _complete_plan(self, query: str, code: str, attempt: int) -> str:
        """The planner's ``code`` completed (:mod:`voxposer.lmp.plan_pipeline`), each change
        recorded as a ``plan_completed`` transcript event."""
        return complete_plan(query, code, self.config, tuple(self.scene.object_names),
                             partial(self.transcript.write, "plan_completed", query=query,
                                     attempt=attempt))

    def _first_messages(self, spec: LMPSpec, query: str) -> tuple[ChatMessage, ...]:
        """The first attempt's conversation of ``spec(query)``: prompt, chosen examples, query."""
        return self.prompt(spec.name).messages(query_message(spec, query, self.scene.object_names),
                                               retrieved=self.config.retrieved_examples)

    def _request(self, spec: LMPSpec, messages: list[ChatMessage] | tuple[ChatMessage, ...],
                 n_prefix: int, n_context: int) -> LLMRequest:
        return LLMRequest(messages=tuple(messages), temperature=self.config.temperature,
                          max_tokens=self.config.max_tokens, stop=self.config.stop,
                          prefix_id=self.prompt(spec.name).prefix_id,
                          prefix_messages=n_prefix if n_prefix < len(messages) - 1 else None,
                          context_messages=n_context if n_context > n_prefix else None)

    def _prefetch_maps(self, code: str) -> None:
        """The first requests of the map programs composer ``code`` calls with literal queries
        (not yet generated), asked together (:mod:`voxposer.lmp.prefetch`)."""
        wanted = [(get_spec(lmp), q) for lmp, q in map_queries(code)
                  if (lmp, q) not in self.code_cache and (lmp, q) not in self._prefetched]
        if len(wanted) < 2:
            return
        requests = [self._request(spec, base, self.prompt(spec.name).n_prefix_messages,
                                  len(base) - 1)
                    for spec, q in wanted for base in (self._first_messages(spec, q),)]
        try:
            responses = self.backend.complete_many(requests)
        except LLMError as exc:  # each call then asks on its own (and meets the error itself)
            logger.info("asking %d map programs together failed: %s", len(requests), exc)
            return
        for (spec, q), response in zip(wanted, responses, strict=True):
            self._prefetched.put(spec.name, q, response)

    def _complete(self, spec: LMPSpec, query: str, messages: list[ChatMessage], n_prefix: int,
                  attempt: int, n_context: int) -> str:
        request = self._request(spec, messages, n_prefix, n_context)
        self.llm_calls += 1
        start = time.monotonic()
        held = self._prefetched.take(spec.name, query) if attempt == 1 else None
        response = held if held is not None else self.backend.complete(request)
        self.transcript.write(
            "llm_call", lmp=spec.name, query=query, attempt=attempt,
            messages=[asdict(m) for m in messages[n_prefix:]], response=response.text,
            model=response.model, cached=response.cached, batched=held is not None,
            seconds=round(response.seconds if held is not None else time.monotonic() - start, 3))
        return response.text

    def _evaluate(self, spec: LMPSpec, query: str, code: str, attempt: int, replay: bool) -> Any:
        start = time.monotonic()
        error = None
        try:
            namespace = self.sandbox.run(code, self._variables(spec, query))
            if spec.role == "object" and is_nothing(namespace.get(spec.result_name or "", 0)):
                raise NothingFound(query, self.scene.object_names)
            result = check_result(spec, namespace, self.scene.grid)
            if spec.role == "object" and isinstance(name := getattr(result, "name", None), str):
                self.intent.alias(query, name)
            if spec.map_kind == "velocity":
                result = self.forms.speed(spec.name, query, result, record=not replay)
            return result
        except Exception as exc:
            error = describe(exc)
            raise
        finally:
            self.transcript.write("exec", lmp=spec.name, query=query, attempt=attempt, code=code,
                                  ok=error is None, error=error,
                                  seconds=round(time.monotonic() - start, 4), replay=replay)
