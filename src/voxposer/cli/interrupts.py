"""Stop signals for long commands: SIGINT and SIGTERM become :class:`Interrupted`.

Inside :func:`stop_signals` both signals raise :class:`Interrupted` (a ``KeyboardInterrupt``) in
the main thread, whatever their handlers were before: a command started in the background by a
non-interactive shell inherits SIGINT *ignored*, and SIGTERM (what ``kill``, ``timeout`` and job
schedulers send) would otherwise end the process at once, without its cleanup. A second signal
while the command is stopping gets the default behaviour (SIGINT: KeyboardInterrupt, SIGTERM:
the process ends), so a stuck stop can still be forced.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from types import FrameType
from typing import Any, Final

#: The signals :func:`stop_signals` turns into :class:`Interrupted`.
STOP_SIGNALS: Final = (signal.SIGINT, signal.SIGTERM)


class Interrupted(KeyboardInterrupt):
    """A stop signal arrived.

    Attributes:
        signum: the signal's number.
    """

    def __init__(self, signum: int) -> None:
        self.signum = int(signum)
        super().__init__(f"stopped by {self.signal_name}")

    @property
    def signal_name(self) -> str:
        """"SIGINT", "SIGTERM"…"""
        try:
            return signal.Signals(self.signum).name
        except ValueError:
            return f"signal {self.signum}"

    @property
    def exit_status(self) -> int:
        """The shell's status for a process ended by the signal: 128 + its number."""
        return 128 + self.signum


def _default(signum: int) -> Any:
    """The default disposition of ``signum`` (SIGINT: Python's KeyboardInterrupt)."""
    return signal.default_int_handler if signum == signal.SIGINT else signal.SIG_DFL


@contextmanager
def stop_signals(signums: Sequence[int] = STOP_SIGNALS) -> Iterator[None]:
    """Raise :class:`Interrupted` on each of ``signums`` while inside (main thread only; in any
    other thread this does nothing, as Python delivers signals to the main thread)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.getsignal(s) for s in signums}

    def handler(signum: int, frame: FrameType | None) -> None:
        for s in signums:  # a second signal while stopping: the default behaviour
            signal.signal(s, _default(s))
        raise Interrupted(signum)

    for s in signums:
        signal.signal(s, handler)
    try:
        yield
    finally:
        for s, old in previous.items():
            signal.signal(s, old if old is not None else _default(s))


__all__ = ["STOP_SIGNALS", "Interrupted", "stop_signals"]
