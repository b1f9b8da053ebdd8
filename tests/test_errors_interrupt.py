"""An interrupt that surfaces through compiled code still reads as an interrupt."""

from voxposer.errors import pending_interrupt


def _system_error_caused_by_an_interrupt() -> SystemError:
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as stop:  # what numba's dispatcher reports when a handler raises
            raise SystemError("CPUDispatcher(...) returned a result with an exception set") from stop
    except SystemError as exc:
        return exc


def test_the_interrupt_behind_a_system_error_is_found() -> None:
    exc = _system_error_caused_by_an_interrupt()
    assert isinstance(pending_interrupt(exc), KeyboardInterrupt)
    wrapped = RuntimeError("a program failed")
    wrapped.__context__ = exc
    assert isinstance(pending_interrupt(wrapped), KeyboardInterrupt)


def test_a_plain_error_has_no_interrupt() -> None:
    try:
        raise ValueError("bad index")
    except ValueError as exc:
        assert pending_interrupt(exc) is None
