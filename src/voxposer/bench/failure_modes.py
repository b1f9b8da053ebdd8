"""Failure reasons normalised to short failure modes, so failures can be counted per task.

A record's failure mode (:func:`failure_mode`), first rule that applies:

* a crash (``error``): ``"crashed: <exception class>"``;
* a program error (``program_error``, e.g. "ExecutionFailedError: sub-task 'push the blue
  block…' failed (stalled): …"): its error class plus the first words of the message, up to the
  first ``:`` or ``;``, normalised as below ("ExecutionFailedError: sub-task failed (stalled)"),
  followed by the mode of the "last error: …" an LMP gave up on;
* else the check's ``reason``, normalised: quoted text, numbers and their units dropped, the
  episode's attribute values replaced by what they are ("end effector 3.2 cm outside the back
  side of the table" → "end effector outside the place"; "the top drawer is open 5.1 cm" →
  "the drawer is open").
"""

from __future__ import annotations

import re
from typing import Any, Final

from voxposer.envs.config import COLORS
from voxposer.places import PLACES

#: words of a program error kept after its class.
PROGRAM_ERROR_WORDS: Final = 6

_QUOTED = re.compile(r"'[^']*'|\"[^\"]*\"")
_NUMBER = re.compile(r"(?:[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?|[-+]?\binf\b|\bnan\b)"
                     r"\s*(?:cm|mm|m/s|m|s|x|%|rad|N)?(?![\w])")
_PLACE = re.compile("|".join(re.escape(p) for p in sorted(PLACES, key=len, reverse=True)))
_COLOURED = re.compile(rf"\b(?:{'|'.join(COLORS)}|grey)\s+(block|line)\b")
_DRAWER = re.compile(r"\b(?:top|middle|bottom)\s+drawer\b")
_EMPTY = re.compile(r"[\[(]\s*[,;:\s]*[\])]")
_DANGLING = re.compile(r"\s*(?:\b(?:for|of|from|to|at|by|than)\b|>=|<=|>|<|=)\s*(?=[\]),;]|$)")
_LAST_ERROR: Final = "last error: "
_CLASS = re.compile(r"^([A-Za-z_][\w.]*(?:Error|Exception|Interrupt|Exit|Warning)?)\s*:")


def normalise_reason(text: str) -> str:
    """``text`` without quoted text, numbers with units and attribute values (see module)."""
    out = _QUOTED.sub("", text)
    out = _PLACE.sub("place", out)
    out = _COLOURED.sub(r"\1", out)
    out = _DRAWER.sub("drawer", out)
    out = _NUMBER.sub("", out)
    for _ in range(3):  # "(outside [, ] for )" → "(outside)" → ""
        out = _EMPTY.sub("", _DANGLING.sub("", out))
    out = re.sub(r"\s+([,;:)\]])", r"\1", out)
    out = re.sub(r"([(\[])\s+", r"\1", out)
    out = re.sub(r"\s{2,}", " ", out)
    out = re.sub(r"([,;:])(?=[,;:])", "", out)
    return out.strip(" ,;:")


def _error_class(text: str) -> str:
    """The exception class a crash text names: its traceback's last line, or "Error: …"."""
    lines = [ln.strip() for ln in text.strip().splitlines() if ln.strip()]
    for line in reversed(lines or [""]):
        found = _CLASS.match(line.removeprefix("error:").strip())
        if found:
            return found.group(1).rsplit(".", 1)[-1]
    return "unknown"


def program_error_mode(text: str) -> str:
    """"ExecutionFailedError: sub-task failed (stalled)" from a ``program_error``."""
    found = _CLASS.match(text.strip())
    if not found:
        return normalise_reason(text)
    rest = text.strip()[found.end():]
    inner = ""
    if _LAST_ERROR in rest:  # a retrying LMP: name the error it finally gave up on too
        rest, last = rest.split(_LAST_ERROR, 1)
        inner = f" — {program_error_mode(last)}"
    head = re.split(r"[:;]", normalise_reason(rest), maxsplit=1)[0]
    words = head.split()[:PROGRAM_ERROR_WORDS]
    return f"{found.group(1)}: {' '.join(words)}".rstrip(": ") + inner


def failure_mode(record: dict[str, Any]) -> str:
    """The failure mode of a (failed) episode record (see module docs)."""
    if record.get("error"):
        return f"crashed: {_error_class(str(record['error']))}"
    if record.get("program_error"):
        return program_error_mode(str(record["program_error"]))
    return normalise_reason(str(record.get("reason", ""))) or "no reason given"


__all__ = ["failure_mode", "normalise_reason", "program_error_mode"]
