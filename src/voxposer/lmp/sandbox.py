"""Run untrusted, LLM-generated Python with RestrictedPython and hard limits.

Generated code is compiled in three passes: a static check (imports, ``try``, ``class``,
``global``, refused names such as ``eval``/``exec``/``open``/``getattr``/``globals``, private and
dunder names, frame/code attributes, ``str.format``), RestrictedPython's transformer (guards every
attribute read, item read, write and iteration), and a rewrite of arithmetic into size-checked
calls (:mod:`voxposer.lmp.sandbox_limits`). At run time the code sees only the names it is given
plus a small set of safe builtins; numpy arrives through a size-limited proxy; a wall-time limit
is enforced with ``sys.settrace`` (per thread, so it works off the main thread too).

Every violation raises :class:`voxposer.errors.SandboxError` naming the refused construct.
Ordinary exceptions of the code itself (``NameError``, ``IndexError``…) propagate unchanged so
that self-correction can show them to the model.

Usable alone::

    sandbox = Sandbox()
    out = sandbox.run("y = np.zeros(3) + x", {"x": 1.0})
    out["y"]  # array([1., 1., 1.])
"""

from __future__ import annotations

import builtins
import contextlib
import logging
import sys
import threading
import time
import types
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from RestrictedPython import PrintCollector
from RestrictedPython.Guards import guarded_iter_unpack_sequence, guarded_unpack_sequence
from scipy.spatial.transform import Rotation

from voxposer.errors import ConfigError, SandboxError
from voxposer.lmp.sandbox_compile import (
    SANDBOX_FILENAME,
    check_attr_name,
    compile_sandboxed,
)
from voxposer.lmp.sandbox_limits import NumpyProxy, SizeGuard, make_binop_guard

logger = logging.getLogger(__name__)

_SAFE_BUILTINS: Final = (
    "abs", "all", "any", "bool", "callable", "chr", "dict", "divmod", "enumerate", "filter",
    "float", "frozenset", "hash", "int", "isinstance", "issubclass", "iter", "len", "list", "map",
    "max", "min", "next", "ord", "repr", "reversed", "round", "set", "slice", "sorted", "str",
    "sum", "tuple", "zip", "None", "True", "False", "ArithmeticError", "AssertionError",
    "Exception", "IndexError", "KeyError", "NameError", "TypeError", "ValueError",
    "ZeroDivisionError", "StopIteration",
)


@dataclass(frozen=True)
class SandboxConfig:
    """Limits of one sandboxed execution.

    Attributes:
        time_limit_s: wall time one execution may spend in generated code [s] (time spent in
            trusted callbacks inside :func:`suspend_time_limit`, e.g. nested LLM calls, is not
            counted).
        max_elements: largest array / sequence generated code may create [elements].
    """

    time_limit_s: float = 10.0
    max_elements: int = 64_000_000

    def __post_init__(self) -> None:
        if not (isinstance(self.time_limit_s, int | float) and 0 < self.time_limit_s <= 3600):
            raise ConfigError(f"SandboxConfig.time_limit_s must be in (0, 3600]; got "
                              f"{self.time_limit_s!r}")
        if not (isinstance(self.max_elements, int) and self.max_elements >= 1000):
            raise ConfigError(f"SandboxConfig.max_elements must be an int >= 1000; got "
                              f"{self.max_elements!r}")


# ----------------------------------------------------------------------------- time limit
_local = threading.local()


def _deadlines() -> list[float | None]:
    if not hasattr(_local, "deadlines"):
        _local.deadlines = []
    return _local.deadlines


def _check_deadline() -> None:
    stack = _deadlines()
    if stack and stack[-1] is not None and time.monotonic() > stack[-1]:
        stack[-1] = None  # raise once; the frames unwind
        raise SandboxError("time limit: the generated code ran too long (an endless loop?)")


def _trace(frame: types.FrameType, event: str, arg: Any) -> Any:
    if frame.f_code.co_filename != SANDBOX_FILENAME:
        return None
    _check_deadline()
    return _trace_local


def _trace_local(frame: types.FrameType, event: str, arg: Any) -> Any:
    if event == "line":
        _check_deadline()
    return _trace_local


@contextlib.contextmanager
def suspend_time_limit() -> Iterator[None]:
    """Stop the clock of the running sandboxed execution(s) while trusted code runs inside.

    Trusted callbacks that may take long (a nested LLM call, the robot executing a plan) wrap
    their work in this, so the caller's time limit counts only its own code.
    """
    stack = _deadlines()
    start = time.monotonic()
    stack.append(None)
    try:
        yield
    finally:
        stack.pop()
        spent = time.monotonic() - start
        for i, deadline in enumerate(stack):
            if deadline is not None:
                stack[i] = deadline + spent


# ------------------------------------------------------------------------------- guards
class _LoggingPrint(PrintCollector):
    """``print`` inside generated code goes to the debug log."""

    def _call_print(self, *objects: Any, **kwargs: Any) -> None:
        kwargs.pop("file", None)
        logger.debug("generated code printed: %s", " ".join(str(o) for o in objects))


def _guarded_getattr(obj: Any, name: str, *default: Any) -> Any:
    check_attr_name(name)
    if isinstance(obj, types.ModuleType):
        raise SandboxError(f"refused: attribute `.{name}` of module {obj.__name__}")
    return getattr(obj, name, *default)


def _guarded_write(obj: Any) -> Any:
    if isinstance(obj, types.ModuleType | type | NumpyProxy | types.FunctionType
                  | types.BuiltinFunctionType):
        raise SandboxError(f"refused: modifying {type(obj).__name__} objects")
    return obj


class Sandbox:
    """Compiles and runs generated code under :class:`SandboxConfig` limits."""

    def __init__(self, config: SandboxConfig | None = None) -> None:
        self.config = config or SandboxConfig()
        self._size = SizeGuard(self.config.max_elements)
        self.numpy = NumpyProxy(np, self._size)
        binop = make_binop_guard(self._size)
        guard = self._size

        def safe_range(*args: int) -> range:
            r = range(*args)
            guard.check(len(r), "range(...)")
            return r

        def safe_pow(a: Any, b: Any, *mod: Any) -> Any:
            return binop("**", a, b) if not mod else builtins.pow(a, b, *mod)

        names = {name: getattr(builtins, name) for name in _SAFE_BUILTINS}
        names.update(range=safe_range, pow=safe_pow, print=print)
        self._builtins = names
        self._guards: dict[str, Any] = {
            "_getattr_": _guarded_getattr,
            "_getitem_": lambda obj, key: obj[key],
            "_write_": _guarded_write,
            "_getiter_": iter,
            "_iter_unpack_sequence_": guarded_iter_unpack_sequence,
            "_unpack_sequence_": guarded_unpack_sequence,
            "_inplacevar_": binop,
            "_binop_": binop,
            "_apply_": lambda f, *a, **k: f(*a, **k),
            "_print_": _LoggingPrint,
            "__name__": "voxposer_lmp",
            "__metaclass__": type,
        }

    def base_globals(self) -> dict[str, Any]:
        """The names every execution sees: safe builtins, guards, ``np``/``numpy``, ``Rotation``."""
        out = dict(self._guards)
        out["__builtins__"] = dict(self._builtins)
        out.update(np=self.numpy, numpy=self.numpy, Rotation=Rotation)
        return out

    def run(self, code: str | types.CodeType, variables: Mapping[str, Any]) -> dict[str, Any]:
        """Execute ``code`` with ``variables`` visible; return the namespace afterwards.

        The namespace is one dict (globals = locals), so functions defined by the code see the
        code's own variables. ``variables`` is not modified.

        Raises:
            SandboxError: a refused construct, or the time or size limit was exceeded.
            SyntaxError, Exception: whatever the generated code itself raised.
        """
        compiled = compile_sandboxed(code) if isinstance(code, str) else code
        namespace = self.base_globals()
        for key in variables:
            if key.startswith("_"):
                raise SandboxError(f"refused: variable name {key!r} starts with '_'")
        namespace.update(variables)
        stack = _deadlines()
        stack.append(time.monotonic() + self.config.time_limit_s)
        previous = sys.gettrace()
        sys.settrace(_trace)
        try:
            exec(compiled, namespace)
        finally:
            sys.settrace(previous)
            stack.pop()
        return namespace
