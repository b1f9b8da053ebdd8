"""The values of the intent checks: an evaluated condition and what ``expect`` recorded."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any


@dataclass(frozen=True)
class Condition:
    """One evaluated post-condition.

    Attributes:
        text: the call as written (``"moved('pink block', toward='right', cm=2)"``).
        held: whether it was true.
        measured: what was measured, in words with units.
    """

    text: str
    held: bool
    measured: str
    #: the helper could not evaluate it (bad arguments, object not visible): not counted
    error: bool = False

    def __post_init__(self) -> None:  # numpy comparisons give numpy booleans
        object.__setattr__(self, "held", bool(self.held))

    def __bool__(self) -> bool:
        return self.held


@dataclass(frozen=True)
class IntentResult:
    """A condition ``expect`` recorded, with the sub-task it followed."""

    subtask: str
    condition: str
    held: bool
    measured: str
    error: bool = False

    def to_json(self) -> dict[str, Any]:
        """A JSON-serialisable dict."""
        return asdict(self)


def call_text(fn: str, *args: Any, **kwargs: Any) -> str:
    """How a helper call reads in a report: ``moved('pink block', toward='right', cm=2)``."""
    parts = [repr(a) for a in args] + [f"{k}={v!r}" for k, v in kwargs.items() if v is not None]
    return f"{fn}({', '.join(parts)})"


__all__ = ["Condition", "IntentResult", "call_text"]
