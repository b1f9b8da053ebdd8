"""Starting, describing and stopping the process sandbox's worker.

The worker (:func:`voxposer.lmp.sandbox_worker.serve`) is forked from multiprocessing's
*forkserver*: a clean, single-threaded process started once, which preloads the sandbox, so a
worker starts in ~50 ms (``spawn``: ~1.3 s each) and inherits none of the caller's threads
(MuJoCo, EGL, a llama.cpp model). As with any spawned child, the caller's main module must be
import-safe (``if __name__ == "__main__":``), and a daemonic process cannot start one.
"""

from __future__ import annotations

import contextlib
import dataclasses
import multiprocessing
import pickle
import shutil
import signal
import tempfile
from collections.abc import Callable
from multiprocessing.connection import Connection
from multiprocessing.process import BaseProcess
from typing import Any, Final

from voxposer.errors import SandboxError
from voxposer.lmp.sandbox_shm import Arena
from voxposer.lmp.sandbox_worker import WorkerSetup, serve

#: Modules the forkserver imports once, so that each worker starts in ~50 ms.
PRELOAD: Final = ["voxposer.lmp.sandbox", "voxposer.lmp.sandbox_worker"]


@dataclasses.dataclass
class WorkerProcess:
    """One worker process and what the parent holds for it."""

    process: BaseProcess
    conn: Connection
    scratch: str
    inbox: Arena  # the worker's arrays (parent-owned)
    outbox: Arena  # the parent's arrays

    def close(self) -> None:
        """Kill the process and free its pipe, arenas and scratch directory (idempotent)."""
        if self.process.is_alive():
            self.process.kill()
        self.process.join(5.0)
        self.conn.close()
        self.inbox.close()
        self.outbox.close()
        shutil.rmtree(self.scratch, ignore_errors=True)


class Slot:
    """Holds the current worker; also what the finalizer closes (no reference to the owner)."""

    def __init__(self) -> None:
        self.worker: WorkerProcess | None = None

    def close(self) -> None:
        if self.worker is not None:
            worker, self.worker = self.worker, None
            with contextlib.suppress(OSError, ValueError):
                worker.conn.send_bytes(pickle.dumps(("close", (), [], None), 5))
            worker.close()


def launch(config: Any, factory: Callable[[Any], Any],
           suspend: Callable[[], contextlib.AbstractContextManager[None]]) -> WorkerProcess:
    """Start a worker for ``config`` (a ``SandboxConfig``) in a fresh scratch directory.

    Raises:
        SandboxError: called from a daemonic process, which may not have children.
    """
    if multiprocessing.current_process().daemon:
        raise SandboxError("isolation='process' cannot start its worker inside a daemonic "
                           "process (a benchmark worker); use isolation='inline' there")
    ctx = multiprocessing.get_context("forkserver")
    ctx.set_forkserver_preload(PRELOAD)
    scratch = tempfile.mkdtemp(prefix="voxposer-sandbox-")
    inbox, outbox = Arena(), Arena()
    parent_conn, child_conn = ctx.Pipe(duplex=True)
    setup = WorkerSetup(factory, suspend, dataclasses.replace(config, isolation="inline"),
                        scratch, config.memory_limit_mb, config.cpu_limit_s,
                        config.max_open_files, (inbox.name, inbox.size))
    process = ctx.Process(target=serve, args=(child_conn, setup), daemon=True,
                          name="voxposer-sandbox")
    process.start()
    child_conn.close()
    return WorkerProcess(process, parent_conn, scratch, inbox, outbox)


def death_cause(exitcode: int | None, config: Any) -> str:
    """What ended a worker with ``exitcode`` (negative: the signal), naming the limit hit."""
    if exitcode is not None and exitcode < 0:
        sig = signal.Signals(-exitcode)
        if sig == signal.SIGXCPU:
            what = (f"CPU limit: the generated code used more than cpu_limit_s="
                    f"{config.cpu_limit_s} s of CPU time")
        elif sig == signal.SIGKILL:
            what = ("the sandbox worker was killed (SIGKILL: the system ran out of memory, "
                    f"or it was killed from outside; memory_limit_mb={config.memory_limit_mb})")
        else:
            what = f"the sandbox worker crashed ({sig.name})"
    else:
        what = f"the sandbox worker exited unexpectedly (exit code {exitcode})"
    return what

