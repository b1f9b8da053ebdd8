"""Run untrusted, LLM-generated Python with RestrictedPython and hard limits.

Generated code is compiled in three passes: a static check (imports, ``try``, ``class``,
``global``, refused names such as ``eval``/``exec``/``open``/``getattr``/``globals``, private and
dunder names, frame/code attributes, ``str.format``), RestrictedPython's transformer (guards every
attribute read, item read, write and iteration), and a rewrite of arithmetic into size-checked
calls (:mod:`voxposer.lmp.sandbox_limits`). At run time the code sees only the names it is given
plus a small set of safe builtins (:mod:`voxposer.lmp.sandbox_builtins`); numpy arrives through a
size- and work-limited proxy (:mod:`voxposer.lmp.sandbox_numpy`); attributes of what it holds come
from an allowlist whose allocating methods are size-checked (:mod:`voxposer.lmp.sandbox_attrs`);
item reads and writes follow the voxel-index rule (:mod:`voxposer.lmp.sandbox_index`); a
wall-time limit is enforced with ``sys.settrace`` (per thread, so it works off the main thread
too); runaway recursion is reported as such.

Every violation raises :class:`voxposer.errors.SandboxError` naming the refused construct.
Ordinary exceptions of the code itself (``NameError``, ``IndexError``…) propagate unchanged so
that self-correction can show them to the model.

With ``SandboxConfig(isolation="process")`` the same checks run inside a persistent worker
process with OS limits on memory, CPU time, open files and file writes
(:mod:`voxposer.lmp.sandbox_process`): a second layer, should the first be escaped.

Usable alone::

    sandbox = Sandbox()
    out = sandbox.run("y = np.zeros(3) + x", {"x": 1.0})
    out["y"]  # array([1., 1., 1.])
"""

from __future__ import annotations

import contextlib
import logging
import sys
import threading
import time
import types
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any, Final, Literal

import numpy as np
from RestrictedPython import PrintCollector
from RestrictedPython.Guards import guarded_iter_unpack_sequence, guarded_unpack_sequence
from scipy.spatial.transform import Rotation

from voxposer.errors import ConfigError, SandboxError
from voxposer.lmp import sandbox_memory
from voxposer.lmp.sandbox_attrs import AttributePolicy
from voxposer.lmp.sandbox_builtins import make_builtins
from voxposer.lmp.sandbox_compile import (
    SANDBOX_FILENAME,
    check_attr_name,
    compile_sandboxed,
)
from voxposer.lmp.sandbox_index import WriteTarget, guarded_getitem
from voxposer.lmp.sandbox_limits import Limits, SizeGuard, make_binop_guard
from voxposer.lmp.sandbox_numpy import NumpyProxy
from voxposer.lmp.sandbox_work import WorkGuard

logger = logging.getLogger(__name__)
#: bytes per element of the size limit: generated code's memory may grow by
#: ``max_elements`` 8-byte elements in all (the memory watch, :mod:`sandbox_memory`).
BYTES_PER_ELEMENT = 8

#: The values of ``SandboxConfig.isolation``.
ISOLATION_MODES: Final = ("inline", "process")


@dataclass(frozen=True)
class SandboxConfig:
    """Limits of one sandboxed execution.

    Attributes:
        time_limit_s: wall time one execution may spend in generated code [s] (time spent in
            trusted callbacks inside :func:`suspend_time_limit`, e.g. nested LLM calls, is not
            counted).
        max_elements: largest array / sequence generated code may create [elements]; times
            8 bytes, also the most memory one execution may add in all (watched every 256
            lines, :mod:`voxposer.lmp.sandbox_memory`).
        max_work: most operations one super-linear call may take [multiply-adds or
            comparisons]: a matrix product, a ``np.linalg`` factorisation, a sort, a
            convolution (:mod:`voxposer.lmp.sandbox_work`). The default, 1e9, is about a second
            of CPU and far above what value-map code on a 100 x 100 x 100 grid needs (sorting
            all 1e6 voxels is 2e7; their coordinates times a 3 x 3 matrix, 9e6).
        isolation: "inline" runs the code in this process (fast); "process" runs it in a
            worker process under the OS limits below as well (:mod:`voxposer.lmp.
            sandbox_process`; measured cost in the README).
        memory_limit_mb: address space of the worker process [MiB] ("process" only).
        cpu_limit_s: CPU time one run may take in the worker [s] ("process" only).
        max_open_files: file descriptors the worker may hold ("process" only).
    """

    time_limit_s: float = 10.0
    max_elements: int = 64_000_000
    max_work: int = 1_000_000_000
    isolation: Literal["inline", "process"] = "inline"
    memory_limit_mb: int = 4096
    cpu_limit_s: float = 30.0
    max_open_files: int = 64

    def __post_init__(self) -> None:
        if not (isinstance(self.time_limit_s, int | float) and 0 < self.time_limit_s <= 3600):
            raise ConfigError(f"SandboxConfig.time_limit_s must be in (0, 3600]; got "
                              f"{self.time_limit_s!r}")
        if not (isinstance(self.max_elements, int) and self.max_elements >= 1000):
            raise ConfigError(f"SandboxConfig.max_elements must be an int >= 1000; got "
                              f"{self.max_elements!r}")
        if not (isinstance(self.max_work, int) and not isinstance(self.max_work, bool)
                and self.max_work >= 1_000_000):
            raise ConfigError(f"SandboxConfig.max_work must be an int >= 1,000,000 "
                              f"[operations]; got {self.max_work!r}")
        if self.isolation not in ISOLATION_MODES:
            raise ConfigError(f"SandboxConfig.isolation must be one of {ISOLATION_MODES}; got "
                              f"{self.isolation!r}")
        if not (_is_int(self.memory_limit_mb) and 256 <= self.memory_limit_mb <= 1 << 20):
            raise ConfigError(f"SandboxConfig.memory_limit_mb must be an int in [256, 1048576] "
                              f"[MiB]; got {self.memory_limit_mb!r}")
        if not (isinstance(self.cpu_limit_s, int | float) and not isinstance(self.cpu_limit_s, bool)
                and 1 <= self.cpu_limit_s <= 3600):
            raise ConfigError(f"SandboxConfig.cpu_limit_s must be in [1, 3600] [s]; got "
                              f"{self.cpu_limit_s!r}")
        if not (_is_int(self.max_open_files) and 16 <= self.max_open_files <= 65536):
            raise ConfigError(f"SandboxConfig.max_open_files must be an int in [16, 65536]; got "
                              f"{self.max_open_files!r}")


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


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
        sandbox_memory.check()
    return _trace_local


@contextlib.contextmanager
def suspend_time_limit() -> Iterator[None]:
    """Stop the clock of the running sandboxed execution(s) while trusted code runs inside.

    Trusted callbacks that may take long (a nested LLM call, the robot executing a plan) wrap
    their work in this, so the caller's time limit counts only its own code.
    """
    stack = _deadlines()
    start, memory = time.monotonic(), sandbox_memory.resident_bytes()
    heap = sandbox_memory.heap_bytes() if sandbox_memory.watching_heap() else None
    stack.append(None)
    try:
        yield
    finally:
        stack.pop()
        after = sandbox_memory.resident_bytes()
        heap_after = sandbox_memory.heap_bytes() if heap is not None else None
        sandbox_memory.discount(after - memory if memory is not None and after is not None else 0,
                                heap_after - heap if heap is not None and heap_after is not None
                                else 0)
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


def _guarded_write(obj: Any) -> WriteTarget:
    if isinstance(obj, types.ModuleType | type | NumpyProxy | types.FunctionType
                  | types.BuiltinFunctionType):
        raise SandboxError(f"refused: modifying {type(obj).__name__} objects")
    return WriteTarget(obj)


class Sandbox:
    """Compiles and runs generated code under :class:`SandboxConfig` limits."""

    def __init__(self, config: SandboxConfig | None = None) -> None:
        self.config = config or SandboxConfig()
        self._process: Any = None  # the ProcessSandbox of isolation="process", made on first use
        self.limits = Limits(SizeGuard(self.config.max_elements),
                             WorkGuard(self.config.max_work))
        self.numpy = NumpyProxy(np, self.limits)
        binop = make_binop_guard(self.limits)
        policy = AttributePolicy(self.limits)

        def getattr_(obj: Any, name: str) -> Any:
            check_attr_name(name)
            return policy.get(obj, name)

        self._builtins = make_builtins(self.limits, binop)
        self._guards: dict[str, Any] = {
            "_getattr_": getattr_,
            "_getitem_": guarded_getitem(self.limits.size),
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
            SandboxError: a refused construct, the time, size or work limit was exceeded, a
                voxel index left the grid (:class:`~voxposer.errors.VoxelIndexError`), or the
                code recursed too deeply.
            SyntaxError, Exception: whatever the generated code itself raised.
        """
        if self.config.isolation == "process":
            return self._isolated().run(code, variables)
        compiled = compile_sandboxed(code) if isinstance(code, str) else code
        namespace = self.base_globals()
        for key in variables:
            if key.startswith("_"):
                raise SandboxError(f"refused: variable name {key!r} starts with '_'")
        namespace.update(variables)
        stack = _deadlines()
        stack.append(time.monotonic() + self.config.time_limit_s)
        sandbox_memory.start(self.config.max_elements * BYTES_PER_ELEMENT)
        previous = sys.gettrace()
        sys.settrace(_trace)
        try:
            exec(compiled, namespace)
        except RecursionError as exc:
            raise SandboxError(
                f"recursion limit: the generated code nested its calls too deeply (more than "
                f"about {sys.getrecursionlimit()} levels; an endless recursion?); use a loop"
            ) from exc
        finally:
            sys.settrace(previous)
            stack.pop()
            sandbox_memory.stop()
        return namespace

    def _isolated(self) -> Any:
        if self._process is None:
            from voxposer.lmp.sandbox_process import ProcessSandbox
            self._process = ProcessSandbox(self, type(self), suspend_time_limit)
        return self._process

    @property
    def worker_pid(self) -> int | None:
        """Process id of the ``isolation="process"`` worker (None: inline, or none running)."""
        return self._process.worker_pid if self._process is not None else None

    def close(self) -> None:
        """Stop the worker process of ``isolation="process"`` (a later run starts a new one)."""
        if self._process is not None:
            self._process.close()
