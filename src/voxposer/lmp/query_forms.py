"""What the runtime says to the model, and does to a query and to a result besides asking it.

- The query's message: the query after the prompt's query prefix (the scene's objects first
  for the LMPs that read them), and the retry message that shows the model its error.

- An exact name: a ``parse_query_obj`` query that names a scene object exactly (after the one
  synonym table) is answered ``ret_val = detect(<name>)`` without the model
  (``LMPConfig.resolve_exact_names``), recorded as a ``resolved`` transcript event.
- A whole description: a ``parse_query_obj`` description the calling program cut short
  ("third block" in "… the third block from the right") gets its relational tail back
  (:mod:`voxposer.lmp.descriptions`, ``LMPConfig.whole_descriptions``), recorded as a
  ``description_completed`` event.
- A stand-in: a ``parse_query_obj`` query a map program wrote that names a coloured object the
  scene lacks ("blue block", the examples' name, in a program for "the back side of the yellow
  block") is asked for the one scene object of that kind its calling query names
  (``LMPConfig.object_stand_in``), recorded as an ``object_substituted`` event: a name neither
  the scene nor the query holds cannot be what the program meant (dev records: retries of map
  programs that wrote the examples' block ended the run with an unknown object). Both are
  worked out once per (query, calling query) (:meth:`QueryForms.rewritten`), not at every
  replan (map programs re-run each one).
- A speed the other way: a velocity map whose set scales all go against its query's words
  gets the words' factor there (:func:`~voxposer.lmp.checks.corrected_speed`,
  ``LMPConfig.correct_speed_direction``), recorded as a ``speed_corrected`` event; a query
  whose map agreed is not checked again (the same code runs at every replan).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from voxposer.catalog import COLOR_NAMES
from voxposer.lmp.checks import corrected_speed
from voxposer.lmp.descriptions import whole_description
from voxposer.lmp.prompt import QUERY_PREFIX, RETRY_PREFIX
from voxposer.lmp.registry import LMPConfig, LMPSpec
from voxposer.lmp.transcript import Transcript
from voxposer.perception.names import normalize_name

RETRY_MESSAGE = (RETRY_PREFIX + "\n{error}\nFix it. Answer with the corrected Python code only, "
                 "no explanation.")


def query_message(spec: LMPSpec, query: str, object_names: tuple[str, ...]) -> str:
    """The user message for ``query`` (with the scene's objects for planner/parse_query_obj)."""
    text = f"{QUERY_PREFIX}{query}"
    if spec.with_objects:
        text = f"objects = {list(object_names)!r}\n{text}"
    return text


class QueryForms:
    """The exact-name, whole-description and speed-direction forms of one runtime.

    Args:
        config: the switches (``resolve_exact_names``, ``whole_descriptions``,
            ``correct_speed_direction``).
        object_names: the scene's object names, read at each call (a scene may change).
        transcript: where each change is recorded.
    """

    def __init__(self, config: LMPConfig, object_names: Callable[[], Sequence[str]],
                 transcript: Transcript) -> None:
        self.config = config
        self._names = object_names
        self.transcript = transcript
        #: (query, calling query) → the query :meth:`rewritten` asks
        self._rewritten: dict[tuple[str, str], str] = {}
        self._speed_agrees: set[str] = set()

    def exact_code(self, lmp: str, query: str) -> str | None:
        """``ret_val = detect(<name>)`` when ``parse_query_obj(query)`` names a scene object
        exactly (recorded); None otherwise."""
        if lmp != "parse_query_obj" or not self.config.resolve_exact_names:
            return None
        key = normalize_name(query)
        exact = next((n for n in self._names() if normalize_name(n) == key), None)
        if exact is None:
            return None
        self.transcript.write("resolved", lmp=lmp, query=query, name=exact)
        return f"ret_val = detect({exact!r})"

    def rewritten(self, lmp: str, query: str, context: str) -> str:
        """``lmp(query)`` as asked from a program whose own query is ``context``: made whole,
        then a stand-in for an absent object (module docs). Worked out once per (query,
        context), each change recorded then: map programs re-run at every replan."""
        if lmp != "parse_query_obj" or not context:
            return query
        if (done := self._rewritten.get((query, context))) is None:
            done = self.stand_in(lmp, self.whole(lmp, query, context), context)
            self._rewritten[(query, context)] = done
        return done

    def whole(self, lmp: str, query: str, context: str) -> str:
        """``query`` made whole from the calling program's query ``context`` (module docs)."""
        if lmp != "parse_query_obj" or not context or not self.config.whole_descriptions:
            return query
        whole = whole_description(query, context, self._names())
        if whole != query:
            self.transcript.write("description_completed", query=query, whole=whole,
                                  context=context)
        return whole

    def stand_in(self, lmp: str, query: str, context: str) -> str:
        """``query`` or, when it names a coloured object the scene lacks, the one scene object
        of that kind (its last word) the calling ``context`` names (module docs)."""
        if lmp != "parse_query_obj" or not context or not self.config.object_stand_in:
            return query
        words = normalize_name(query).split()
        names = self._names()
        if len(words) != 2 or words[0] not in COLOR_NAMES \
                or any(normalize_name(n) == " ".join(words) for n in names):
            return query
        said = f" {normalize_name(context)} "
        named = [n for n in names if normalize_name(n).split()[-1:] == words[-1:]
                 and re.search(rf"\b{re.escape(normalize_name(n))}\b", said)]
        if len(named) != 1:
            return query
        self.transcript.write("object_substituted", query=query, name=named[0], context=context)
        return named[0]

    def speed(self, lmp: str, query: str, velocity: Any, *, record: bool) -> Any:
        """``velocity`` (a checked velocity map) turned to its query's direction when it goes
        the other way (module docs); ``record``: write the event (not on a replay)."""
        if not self.config.correct_speed_direction or query in self._speed_agrees \
                or not isinstance(velocity, np.ndarray):
            return velocity
        fix = corrected_speed(query, velocity)
        if fix is None:
            self._speed_agrees.add(query)
            return velocity
        if record:
            self.transcript.write("speed_corrected", lmp=lmp, query=query, why=fix[1])
        return fix[0]


__all__ = ["RETRY_MESSAGE", "QueryForms", "query_message"]
