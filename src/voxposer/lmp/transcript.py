"""A run's transcript: prompts, responses, executed code and errors as JSON lines.

One line per event, written and flushed as it happens (a crashed run keeps what it did):

* ``{"event": "prompt", "lmp", "messages"}`` once per LMP: its few-shot prefix;
* ``{"event": "llm_call", "lmp", "query", "attempt", "messages", "response", "model",
  "seconds", "cached"}``: ``messages`` are those after the prefix (the query and any retries);
* ``{"event": "exec", "lmp", "query", "attempt", "code", "ok", "error", "seconds", "replay"}``:
  one execution of generated code (``replay`` is true when cached code was re-run on a fresh
  observation, without an LLM call);
* ``{"event": "execute", "subtask", "success", "message"}``: what one ``execute`` call did on
  the robot (reached, or why not — including moves that ended away from their targets).
"""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path
from typing import Any


def _default(value: Any) -> Any:
    if hasattr(value, "tolist"):
        return value.tolist()
    return repr(value)


class Transcript:
    """Appends events to a JSONL file (or only keeps them in memory when ``path`` is None).

    Attributes:
        path: the JSONL file, or None.
        events: every event written so far (in memory, for tests and summaries).
    """

    def __init__(self, path: str | Path | None = None) -> None:
        self.path = Path(path) if path is not None else None
        self.events: list[dict[str, Any]] = []
        self._lock = threading.Lock()
        self._prompts: set[str] = set()
        if self.path is not None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.path.write_text("")

    def write(self, event: str, **fields: Any) -> None:
        """Record one event (``fields`` must be JSON-serialisable or array-like)."""
        record = {"event": event, "time": round(time.time(), 3), **fields}
        with self._lock:
            self.events.append(record)
            if self.path is not None:
                with self.path.open("a", encoding="utf-8") as fh:
                    fh.write(json.dumps(record, default=_default, ensure_ascii=False) + "\n")

    def prompt_once(self, lmp: str, messages: list[dict[str, str]]) -> None:
        """Record an LMP's few-shot prefix the first time it is used."""
        if lmp in self._prompts:
            return
        self._prompts.add(lmp)
        self.write("prompt", lmp=lmp, messages=messages)
