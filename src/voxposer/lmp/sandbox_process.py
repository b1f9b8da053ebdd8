"""Process isolation: generated code runs in a persistent worker process with OS limits.

``SandboxConfig(isolation="process")`` makes :meth:`Sandbox.run <voxposer.lmp.sandbox.
Sandbox.run>` hand the code to a :class:`ProcessSandbox`. Its worker
(:mod:`voxposer.lmp.sandbox_worker`) is forked from multiprocessing's *forkserver*
(:mod:`voxposer.lmp.sandbox_launch`), started on the first run, reused, and replaced when it
dies. Inside it the in-process sandbox still applies: two layers.

Protocol (one pipe; every message is ``(kind, head, blobs, arena)``, blobs encoded by
:mod:`voxposer.lmp.sandbox_codec`, large arrays in :mod:`voxposer.lmp.sandbox_shm` arenas):

* parent → worker: ``run`` (code, variables), ``return`` / ``raise`` (the answer to a request),
  ``grown`` (a larger arena for the worker's arrays), ``close``;
* worker → parent: ``ready``, ``done`` (the namespace: every name the code left that can cross),
  ``error`` (the exception), ``call`` / ``getattr`` / ``getitem`` (a proxy's request: the parent
  does it on the real object and answers; an answer may itself run a nested program first),
  ``grow``.

What the worker sends is unpickled with an allowlist of plain types (nothing it sends can make
the parent import or call anything). Exceptions keep their type, message and attributes; an
exception a callback raised comes back as that very object. The wall-time limit is enforced here
too: a worker that has not answered ``time_limit_s`` + :data:`GRACE_S` after a run started (time
in callbacks excluded) is killed. A dead worker (a limit's signal, a segfault, a kill) ends the run
with a :class:`~voxposer.errors.SandboxError` naming the cause; the next run gets a fresh worker.

Runs are serialised (one worker, one lock); nested runs from callbacks of the same thread are
fine. A daemonic process (a benchmark worker) cannot start the worker: use inline isolation there.
"""

from __future__ import annotations

import contextlib
import logging
import marshal
import pickle
import threading
import time
import types
import weakref
from collections.abc import Callable, Mapping
from typing import Any, Final, Protocol

from voxposer.errors import SandboxError
from voxposer.lmp.sandbox_attrs import AttributePolicy
from voxposer.lmp.sandbox_codec import Decoder, exception_info, rebuild_exception
from voxposer.lmp.sandbox_compile import check_attr_name
from voxposer.lmp.sandbox_handles import Handles, ParentEncoder, prepare
from voxposer.lmp.sandbox_launch import Slot, WorkerProcess, death_cause, launch
from voxposer.lmp.sandbox_limits import Limits
from voxposer.lmp.sandbox_shm import Arena

logger = logging.getLogger(__name__)

#: How long past ``time_limit_s`` the parent waits for a silent worker before killing it [s].
GRACE_S: Final = 0.5
#: How long a new worker may take to report ready [s] (the first start boots the forkserver).
START_TIMEOUT_S: Final = 60.0


class InlineSandbox(Protocol):
    """What the process sandbox needs of the in-process one (``voxposer.lmp.sandbox.Sandbox``)."""

    config: Any
    limits: Limits

    def base_globals(self) -> dict[str, Any]: ...


class ProcessSandbox:
    """Runs generated code in a limited worker process (module docs).

    Args:
        inline: the in-process sandbox (its config, limits and base names are used here).
        factory: builds the worker's in-process sandbox from a config (the ``Sandbox`` class).
        suspend: the in-process ``suspend_time_limit`` (the worker pauses its clock with it).
    """

    def __init__(self, inline: InlineSandbox, factory: Callable[[Any], Any],
                 suspend: Callable[[], contextlib.AbstractContextManager[None]]) -> None:
        self.inline = inline
        self.config = inline.config
        self._factory = factory
        self._suspend = suspend
        self._policy = AttributePolicy(inline.limits)
        self._lock = threading.RLock()
        self._slot = Slot()
        self._depth = 0
        self._handles = Handles()
        self._errors: list[BaseException] = []
        self._finalizer = weakref.finalize(self, self._slot.close)

    @property
    def worker_pid(self) -> int | None:
        """The current worker's process id (None before the first run or after a failure)."""
        worker = self._slot.worker
        return worker.process.pid if worker is not None else None

    def close(self) -> None:
        """Stop the worker (a later run starts a new one)."""
        with self._lock:
            self._slot.close()

    def run(self, code: str | types.CodeType, variables: Mapping[str, Any]) -> dict[str, Any]:
        """Like the in-process ``Sandbox.run``, in the worker; returns the namespace (the base
        names, then every name the code left whose value can cross back)."""
        with self._lock:
            if self._depth == 0 and not self._idle_worker_ok():
                self._start()
            worker = self._slot.worker
            if worker is None:
                raise SandboxError("the sandbox worker died during an enclosing run")
            self._depth += 1
            try:
                head = ((marshal.dumps(code), True) if isinstance(code, types.CodeType)
                        else (str(code), False))
                self._send(worker, "run", head, list(prepare(variables, self._handles)))
                return self._serve(worker)
            except Exception:
                raise
            except BaseException:
                self._discard(worker)  # KeyboardInterrupt & co.: the protocol is out of step
                raise
            finally:
                self._depth -= 1
                if self._depth == 0:
                    self._handles.clear()
                    self._errors.clear()

    # ---------------------------------------------------------------------- worker life
    def _idle_worker_ok(self) -> bool:
        """Whether an idle worker is there and alive (a dead one's pipe reads as EOF)."""
        worker = self._slot.worker
        return (worker is not None and worker.process.is_alive()
                and not worker.conn.poll(0))

    def _start(self) -> None:
        self._slot.close()
        worker = launch(self.config, self._factory, self._suspend)
        self._slot.worker = worker
        kind, _, _ = self._receive(worker, time.monotonic() + START_TIMEOUT_S, starting=True)
        if kind != "ready":
            self._discard(worker)
            raise SandboxError(f"the sandbox worker sent {kind!r} instead of 'ready'")
        logger.debug("sandbox worker %d started", worker.process.pid)

    def _discard(self, worker: WorkerProcess) -> None:
        if self._slot.worker is worker:
            self._slot.worker = None
        worker.close()

    def _died(self, worker: WorkerProcess) -> SandboxError:
        worker.process.join(2.0)
        code = worker.process.exitcode
        self._discard(worker)
        return SandboxError(f"{death_cause(code, self.config)}; a fresh worker runs the next "
                            "program")

    # -------------------------------------------------------------------- messages
    def _send(self, worker: WorkerProcess, kind: str, head: tuple[Any, ...], values: list[Any]
              ) -> None:
        encoder = ParentEncoder(self._handles)
        blobs = [encoder.dumps(v) for v in values]
        if encoder.nbytes > worker.outbox.size:
            old, worker.outbox = worker.outbox, Arena(max(encoder.nbytes, 2 * worker.outbox.size))
            old.close()
        encoder.write(worker.outbox.buf)
        arena = (worker.outbox.name, worker.outbox.size)
        try:
            worker.conn.send_bytes(pickle.dumps((kind, head, blobs, arena), 5))
        except OSError:  # a broken pipe: the worker died
            raise self._died(worker) from None

    def _receive(self, worker: WorkerProcess, deadline: float, starting: bool = False
                 ) -> tuple[str, tuple[Any, ...], list[bytes]]:
        remaining = deadline - time.monotonic()
        if remaining <= 0 or not worker.conn.poll(remaining):
            self._discard(worker)
            if starting:
                raise SandboxError(f"the sandbox worker did not start within "
                                   f"{START_TIMEOUT_S} s")
            raise SandboxError(
                f"time limit: the generated code ran longer than time_limit_s="
                f"{self.config.time_limit_s} s and did not stop (stuck in one long call?); "
                "the sandbox worker was killed")
        try:
            data = worker.conn.recv_bytes()
        except (EOFError, OSError):
            raise self._died(worker) from None
        try:
            kind, head, blobs, _ = Decoder(data, None, _no_handle, restricted=True).load()
            return str(kind), tuple(head), [bytes(b) for b in blobs]
        except Exception as exc:
            self._discard(worker)
            raise SandboxError(f"the sandbox worker sent a malformed message ({exc})") from None

    def _decode(self, worker: WorkerProcess, blob: bytes, arrays: dict[int, Any] | None = None
                ) -> Any:
        decoder = Decoder(blob, worker.inbox.buf, lambda pid: self._handles.get(pid[1]),
                          restricted=True)
        if arrays is not None:
            decoder.share_arrays(arrays)
        return decoder.load()

    # ------------------------------------------------------------------------ serving
    def _serve(self, worker: WorkerProcess) -> dict[str, Any]:
        deadline = time.monotonic() + self.config.time_limit_s + GRACE_S
        while True:
            kind, head, blobs = self._receive(worker, deadline)
            if kind == "done":
                arrays: dict[int, Any] = {}
                namespace = self.inline.base_globals()
                for name, blob in zip(head[1], blobs, strict=True):
                    namespace[str(name)] = self._decode(worker, blob, arrays)
                if head[0]:
                    self._discard(worker)  # it used most of its CPU budget: retire it
                return namespace
            if kind == "error":
                exc = self._decode(worker, blobs[0])
                if head[0]:
                    self._discard(worker)
                origin = exc[5] if isinstance(exc, tuple) and len(exc) == 6 else None
                if isinstance(origin, int) and 0 <= origin < len(self._errors):
                    raise self._errors[origin]
                raise rebuild_exception(exc)
            start = time.monotonic()
            self._answer(worker, kind, head, blobs)
            deadline += time.monotonic() - start

    def _answer(self, worker: WorkerProcess, kind: str, head: tuple[Any, ...], blobs: list[bytes]
                ) -> None:
        """Do a worker's request and send the answer (module docs)."""
        if kind == "grow":
            self._grow(worker, int(head[0]))
            return
        try:
            result = self._request(worker, kind, head, blobs)
        except Exception as exc:
            if self._slot.worker is not worker:
                raise  # the worker died in a nested run: this run ends with that error
            self._errors.append(exc)
            self._send(worker, "raise", (len(self._errors) - 1,),
                       [exception_info(exc, len(self._errors) - 1)])
            return
        if self._slot.worker is not worker:
            raise SandboxError("the sandbox worker was replaced during a callback of this run")
        self._send(worker, "return", (), [result])

    def _request(self, worker: WorkerProcess, kind: str, head: tuple[Any, ...], blobs: list[bytes]
                 ) -> Any:
        obj = self._handles.get(head[0])
        if kind == "call":
            args, kwargs = self._decode(worker, blobs[0])
            return obj(*args, **{str(k): v for k, v in kwargs.items()})
        if kind == "getattr":
            check_attr_name(str(head[1]))
            return self._policy.get(obj, str(head[1]))
        if kind == "getitem":
            return obj[self._decode(worker, blobs[0])]
        raise SandboxError(f"the sandbox worker sent an unknown request {kind!r}")

    def _grow(self, worker: WorkerProcess, nbytes: int) -> None:
        limit = self.config.memory_limit_mb * 1024 * 1024
        if not 0 < nbytes <= limit:
            exc = SandboxError(f"memory limit: the generated code's result needs {nbytes} "
                               f"bytes, more than memory_limit_mb={self.config.memory_limit_mb}")
            self._send(worker, "raise", (-1,), [exception_info(exc)])
            return
        old, worker.inbox = worker.inbox, Arena(max(nbytes, 2 * worker.inbox.size))
        old.close()
        self._send(worker, "grown", (worker.inbox.name, worker.inbox.size), [])


def _no_handle(pid: Any) -> Any:
    raise pickle.UnpicklingError("a handle in a message envelope")
