"""The sandbox worker process: OS limits first, then generated code run for the parent.

:func:`serve` is the entry point of the worker that :mod:`voxposer.lmp.sandbox_process` starts.
It lowers its own limits (address space, CPU seconds, open files, file size 0, no core dumps),
moves into a scratch directory, points stdout/stderr at ``/dev/null``, closes every inherited
file descriptor except its pipe, and then serves ``run`` requests with the ordinary in-process
:class:`~voxposer.lmp.sandbox.Sandbox` (RestrictedPython, the numpy proxy, the allowlist, the
time limit): both layers apply.

While generated code runs, a call of a caller's callable (a proxy, :mod:`voxposer.lmp.remote`)
sends a request to the parent and waits, with the time limit suspended, for its result. The parent
may answer with a nested ``run`` (an LMP that runs another LMP's code); the worker runs it on the
same stack, like the in-process sandbox does.

This module does not import :mod:`voxposer.lmp.sandbox` (that imports the process sandbox, which
starts this); the sandbox class and its ``suspend_time_limit`` arrive in :class:`WorkerSetup`.
"""

from __future__ import annotations

import contextlib
import marshal
import math
import os
import pickle
import resource
import signal
import sys
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing.connection import Connection
from typing import Any, Final

from voxposer.errors import SandboxError
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.remote import ApiMethod, ApiSpec, RemoteCallable, RemoteObject, RemoteScene
from voxposer.lmp.sandbox_codec import (
    Decoder,
    Encoder,
    NotTransferable,
    encode_exception,
    rebuild_exception,
)
from voxposer.lmp.sandbox_shm import MappedArena

#: The worker's CPU seconds over its whole life are capped at this many times ``cpu_limit_s``;
#: a worker near the cap retires after its run and a fresh one serves the next.
CPU_LIFETIME_RUNS: Final = 10


@dataclass(frozen=True)
class WorkerSetup:
    """What a worker is started with (pickled to it).

    Attributes:
        factory: builds the in-process sandbox from ``config`` (the ``Sandbox`` class).
        suspend: the in-process sandbox's ``suspend_time_limit``.
        config: the ``SandboxConfig`` with ``isolation="inline"``.
        scratch: the worker's working directory (created and removed by the parent).
        memory_limit_mb: RLIMIT_AS [MiB].
        cpu_limit_s: CPU time one run may use [s] (RLIMIT_CPU, re-armed per run).
        max_open_files: RLIMIT_NOFILE [descriptors].
        arena: (name, size [bytes]) of the parent's arena for the worker's arrays.
    """

    factory: Callable[[Any], Any]
    suspend: Callable[[], contextlib.AbstractContextManager[None]]
    config: Any
    scratch: str
    memory_limit_mb: int
    cpu_limit_s: float
    max_open_files: int
    arena: tuple[str, int]


def serve(conn: Connection, setup: WorkerSetup) -> None:
    """Worker entry point: apply the limits, then answer the parent until it closes."""
    hard_cpu = apply_limits(setup, keep_fd=conn.fileno())
    session = _Session(conn, setup, hard_cpu)
    with contextlib.suppress(EOFError, OSError):  # the parent went away
        session.loop()


def apply_limits(setup: WorkerSetup, keep_fd: int) -> int:
    """Lower this process's limits and isolate it (module docs); returns the hard CPU cap [s]."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a file write fails with EFBIG instead
    sys.dont_write_bytecode = True
    os.chdir(setup.scratch)
    null = os.open(os.devnull, os.O_RDWR)
    for fd in (0, 1, 2):
        os.dup2(null, fd)
    os.close(null)
    for name in os.listdir("/proc/self/fd"):
        fd = int(name)
        if fd > 2 and fd != keep_fd:
            with contextlib.suppress(OSError):
                os.close(fd)
    used = _cpu_used()
    hard_cpu = math.ceil(used + setup.cpu_limit_s * CPU_LIFETIME_RUNS)
    memory = setup.memory_limit_mb * 1024 * 1024
    for limit, value in ((resource.RLIMIT_CORE, 0), (resource.RLIMIT_FSIZE, 0),
                         (resource.RLIMIT_NOFILE, setup.max_open_files),
                         (resource.RLIMIT_AS, memory)):
        resource.setrlimit(limit, (value, value))
    resource.setrlimit(resource.RLIMIT_CPU, (math.ceil(used + setup.cpu_limit_s), hard_cpu))
    return hard_cpu


def _cpu_used() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


class _WorkerEncoder(Encoder):
    """What the worker may send: data, and the proxies (and API methods) it was given."""

    def __init__(self, reverse: dict[int, int]) -> None:
        super().__init__()
        self._reverse = reverse

    def other(self, obj: Any) -> tuple[Any, ...]:
        index = self._reverse.get(id(obj))
        if index is None:
            raise NotTransferable(f"a {type(obj).__name__} made by the generated code cannot "
                                  "leave the sandbox (only data and the objects it was given)")
        return ("h", index)


class _Session:
    """The worker's side of the protocol (see :mod:`voxposer.lmp.sandbox_process`)."""

    def __init__(self, conn: Connection, setup: WorkerSetup, hard_cpu: int) -> None:
        self.conn = conn
        self.setup = setup
        self.hard_cpu = hard_cpu
        self.sandbox = setup.factory(setup.config)
        self.base = frozenset(self.sandbox.base_globals())
        self.inbox: MappedArena | None = None
        self.outbox = MappedArena(*setup.arena)
        self.depth = 0
        self.handles: dict[int, Any] = {}  # parent handle → proxy / API method (this run)
        self.reverse: dict[int, int] = {}  # id(proxy) → parent handle
        self.origins: dict[int, tuple[int, BaseException]] = {}  # id(exc) → parent's index
        self.apis: dict[int, LMPAPI] = {}

    # ---------------------------------------------------------------------- messages
    def loop(self) -> None:
        self.conn.send_bytes(pickle.dumps(("ready", (), [], None), 5))
        while True:
            kind, head, blobs = self.receive()
            if kind == "close":
                return
            if kind != "run":
                raise SandboxError(f"sandbox worker: unexpected message {kind!r}")
            self.run(head, blobs)

    def receive(self) -> tuple[str, tuple[Any, ...], list[bytes]]:
        kind, head, blobs, arena = pickle.loads(self.conn.recv_bytes())  # the parent: trusted
        if arena is not None and (self.inbox is None or self.inbox.name != arena[0]):
            if self.inbox is not None:
                self.inbox.close()
            self.inbox = MappedArena(*arena)
        return kind, head, blobs

    def decode(self, blob: bytes) -> Any:
        buf = self.inbox.buf if self.inbox is not None else None
        return Decoder(blob, buf, self._proxy, restricted=False).load()

    def send(self, kind: str, head: tuple[Any, ...], values: list[Any]) -> None:
        """Encode ``values`` (may raise NotTransferable before anything is sent) and send."""
        encoder = _WorkerEncoder(self.reverse)
        blobs = [encoder.dumps(v) for v in values]
        self._send_encoded(kind, head, blobs, encoder)

    def _send_encoded(self, kind: str, head: tuple[Any, ...], blobs: list[bytes],
                      encoder: Encoder) -> None:
        if encoder.nbytes > self.outbox.size:
            self.conn.send_bytes(pickle.dumps(("grow", (encoder.nbytes,), [], None), 5))
            reply, grown, payload = self.receive()
            if reply != "grown":
                raise rebuild_exception(self.decode(payload[0]))
            self.outbox.close()
            self.outbox = MappedArena(*grown)
        encoder.write(self.outbox.buf)
        self.conn.send_bytes(pickle.dumps((kind, head, blobs, None), 5))

    def request(self, kind: str, index: int, *payload: Any) -> Any:
        """A proxy's call, attribute read or item read, done by the parent (:class:`Link`)."""
        with self.setup.suspend():
            try:
                if kind == "call":
                    self.send("call", (index,), [(tuple(payload[0]), dict(payload[1]))])
                elif kind == "getattr":
                    self.send("getattr", (index, str(payload[0])), [])
                else:
                    self.send("getitem", (index,), [payload[0]])
            except NotTransferable as exc:
                raise SandboxError(f"refused: {exc}") from None
            return self._wait_reply()

    def _wait_reply(self) -> Any:
        while True:
            kind, head, blobs = self.receive()
            if kind == "return":
                return self.decode(blobs[0])
            if kind == "raise":
                exc = rebuild_exception(self.decode(blobs[0]))
                self.origins[id(exc)] = (int(head[0]), exc)
                raise exc
            if kind != "run":
                raise SandboxError(f"sandbox worker: unexpected message {kind!r}")
            self.run(head, blobs)  # a nested LMP call: run it on this stack

    # -------------------------------------------------------------------------- runs
    def run(self, head: tuple[Any, ...], blobs: list[bytes]) -> None:
        """Run one program and send its namespace (``done``) or its exception (``error``)."""
        code, is_code_object = head
        self.depth += 1
        try:
            if self.depth == 1:
                soft = min(self.hard_cpu, math.ceil(_cpu_used() + self.setup.cpu_limit_s))
                resource.setrlimit(resource.RLIMIT_CPU, (soft, self.hard_cpu))
            variables = self._variables(blobs)
            namespace = self.sandbox.run(marshal.loads(code) if is_code_object else code,
                                         variables)
            self._send_namespace(namespace)
        except MemoryError:
            self.send_error(SandboxError(
                f"memory limit: the generated code needed more memory than the sandbox "
                f"worker's memory_limit_mb={self.setup.memory_limit_mb} MiB"), fatal=True)
        except Exception as exc:
            self.send_error(exc)
        finally:
            self.depth -= 1
            if self.depth == 0:
                self.handles.clear()
                self.reverse.clear()
                self.origins.clear()
                self.apis.clear()

    def _retire(self) -> bool:
        return self.depth == 1 and _cpu_used() + self.setup.cpu_limit_s >= self.hard_cpu - 1

    def send_error(self, exc: BaseException, fatal: bool = False) -> None:
        origin = self.origins.get(id(exc))
        encoder = _WorkerEncoder(self.reverse)
        blob = encode_exception(encoder, exc, origin[0] if origin and origin[1] is exc else None)
        self._send_encoded("error", (fatal or self._retire(),), [blob], encoder)

    def _send_namespace(self, namespace: dict[str, Any]) -> None:
        encoder = _WorkerEncoder(self.reverse)
        names, blobs = [], []
        for name, value in namespace.items():
            if name in self.base:
                continue
            try:
                blobs.append(encoder.dumps(value))
            except (NotTransferable, pickle.PicklingError, TypeError, AttributeError):
                continue  # a function the code defined, a generator…: stays in the worker
            names.append(name)
        self._send_encoded("done", (self._retire(), tuple(names)), blobs, encoder)

    # ------------------------------------------------------------------ variables in
    def _proxy(self, pid: tuple[Any, ...]) -> Any:
        _, index, is_callable, text = pid
        if index not in self.handles:
            cls = RemoteCallable if is_callable else RemoteObject
            self._register(index, cls(self, index, text))
        return self.handles[index]

    def _register(self, index: int, obj: Any) -> None:
        self.handles[index] = obj
        self.reverse[id(obj)] = index

    def _variables(self, blobs: list[bytes]) -> dict[str, Any]:
        variables: dict[str, Any] = self.decode(blobs[0])
        specs: list[ApiSpec] = self.decode(blobs[1])
        for name, value in variables.items():
            if isinstance(value, ApiMethod):
                if value.api not in self.apis:
                    self.apis[value.api] = LMPAPI(RemoteScene(specs[value.api]))
                obj: Any = self.apis[value.api]
                for part in value.attr.split("."):
                    obj = getattr(obj, part)
                self._register(value.handle, obj)
                variables[name] = obj
        return variables
