"""How the LMP runtime words and classifies failures of generated code (the model reads these).

:func:`describe` turns an exception into the sentence the model sees when it retries;
:func:`give_up` chooses the error an LMP raises when it stops trying; :class:`NoRetry` marks a
failure that must not be retried (the code already had side effects); :class:`NothingFound` is
object code that found nothing.
"""

from __future__ import annotations

from typing import Any

from voxposer.errors import LMPFailedError, SandboxError, UnknownObjectError, UnresolvedObjectError


class NothingFound(UnknownObjectError):
    """Object code that found nothing (``ret_val`` None or empty) for its query."""


def is_nothing(value: Any) -> bool:
    """Whether an object LMP's result says "no such object": None or an empty list/tuple."""
    return value is None or (isinstance(value, list | tuple) and not value)


def give_up(lmp: str, query: str, attempts: list[dict[str, str]],
             cause: BaseException | None) -> LMPFailedError | UnresolvedObjectError:
    """The error of an LMP that gives up: an unknown object stays one (for every enclosing LMP
    to pass on), anything else is an :class:`LMPFailedError` with every attempt."""
    if isinstance(cause, UnknownObjectError):
        return UnresolvedObjectError(cause.name, cause.known, lmp=lmp, query=query,
                                     attempts=attempts)
    return LMPFailedError(lmp, query, attempts)


class NoRetry(Exception):
    """Wraps a failure of the execute handler so it propagates without self-correction."""

    def __init__(self, original: BaseException) -> None:
        super().__init__(str(original))
        self.original = original


def describe(exc: BaseException) -> str:
    if isinstance(exc, NoRetry):
        exc = exc.original
    if isinstance(exc, NothingFound):
        return (f"UnknownObjectError: {exc} (`ret_val` holds no object). Assign "
                "`ret_val = detect(<one of those names>)` if one of them is meant; if none is, "
                "leave `ret_val = None`")
    if isinstance(exc, SyntaxError) and not isinstance(exc, SandboxError):
        return f"SyntaxError: {exc.msg} (line {exc.lineno}: {(exc.text or '').strip()})"
    if isinstance(exc, ValueError) and "read-only" in str(exc):
        return (f"{type(exc).__name__}: {exc} (a detected object's occupancy cannot be changed: "
                "copy it first, e.g. `occ = obj.occupancy.copy()`, and change the copy)")
    return f"{type(exc).__name__}: {exc}"
