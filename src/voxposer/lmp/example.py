"""One few-shot example of a prompt or an example bank."""

from __future__ import annotations

from typing import NamedTuple


class Example(NamedTuple):
    """One few-shot example: the user turn, the assistant's answer, the tasks it demonstrates."""

    user: str
    assistant: str
    tasks: frozenset[str] = frozenset()


__all__ = ["Example"]
