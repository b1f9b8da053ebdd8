"""Process isolation: same results as in-process, OS limits that hold past RestrictedPython,
callbacks into the parent, and a worker that is replaced when it dies."""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.lmp.escaped_sandbox import EscapedSandbox
from voxposer.errors import ConfigError, SandboxError, UnknownObjectError
from voxposer.lmp import make_tabletop_scene
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.object_view import ObjectView
from voxposer.lmp.sandbox import Sandbox, SandboxConfig, suspend_time_limit
from voxposer.lmp.sandbox_process import ProcessSandbox

MAP_CODE = """
obj = detect('blue block')
affordance_map = get_empty_affordance_map()
set_voxel_by_radius(affordance_map, obj.position, 3, 1)
affordance_map[obj.aabb[0][0]:obj.aabb[1][0], :, 0] = 0.5
ret_val = affordance_map
top = obj.position + [0, 0, cm2index(5, 'z')]
"""


FD_CODE = """import os
cwd = os.getcwd()
fds = {}
for fd in os.listdir('/proc/self/fd'):
    try:
        fds[fd] = os.readlink('/proc/self/fd/' + fd)
    except OSError:
        fds[fd] = None
"""


@pytest.fixture(scope="module")
def process() -> Sandbox:
    sandbox = Sandbox(SandboxConfig(time_limit_s=1.0, isolation="process"))
    yield sandbox
    sandbox.close()


@pytest.fixture(scope="module")
def api() -> LMPAPI:
    return LMPAPI(make_tabletop_scene())


def _escaped(**config: Any) -> ProcessSandbox:
    """A process sandbox whose worker runs code unrestricted: only the OS limits apply."""
    inline = Sandbox(SandboxConfig(isolation="process", **config))
    return ProcessSandbox(inline, EscapedSandbox, suspend_time_limit)


def _view() -> ObjectView:
    occupancy = np.zeros((100, 100, 100), bool)
    occupancy[10:20, 10:20, 0:5] = True
    arrays = (np.array([15, 15, 2]), np.array([[10, 10, 0], [19, 19, 4]]), occupancy,
              np.array([0.0, 0.0, 1.0]), np.zeros(3), np.zeros((2, 3)))
    for arr in arrays:
        arr.flags.writeable = False  # as ObjectView.from_detection makes them
    return ObjectView("mug", *arrays)


def test_value_map_program_gives_the_same_result_in_both_modes(process: Sandbox, api: LMPAPI
                                                               ) -> None:
    variables = dict(api.namespace())
    inline = Sandbox().run(MAP_CODE, variables)
    isolated = process.run(MAP_CODE, variables)
    assert isolated["ret_val"].dtype == np.float32 and isolated["ret_val"].shape == (100,) * 3
    np.testing.assert_array_equal(isolated["ret_val"], inline["ret_val"])
    np.testing.assert_array_equal(isolated["top"], inline["top"])
    assert isinstance(isolated["obj"], ObjectView) and isolated["obj"].name == "blue block"
    assert isolated["detect"] is variables["detect"]  # the caller's objects come back as given


def test_a_callback_returning_an_object_with_arrays(process: Sandbox) -> None:
    calls: list[str] = []

    def detect(name: str) -> ObjectView:
        calls.append(name)
        return _view()

    code = ("o = detect('mug')\nn = int(o.occupancy.sum())\nbox = o.aabb\nocc = o.occupancy\n"
            "m = np.zeros((100, 100, 100))\nm[o.occupancy] = 1.0\n")
    out = process.run(code, {"detect": detect})
    assert calls == ["mug"] and out["n"] == 500 and out["m"].sum() == 500
    np.testing.assert_array_equal(out["box"], _view().aabb)
    assert not out["occ"].flags.writeable  # read-only as the caller made it
    with pytest.raises(ValueError, match="read-only"):
        process.run("o = detect('mug')\no.position[0] = 3", {"detect": detect})


def test_proxied_objects_follow_the_caller_rules(process: Sandbox) -> None:
    class Program:
        """Like an ObjectProgram: callable, with fields read on demand."""

        position = np.array([1, 2, 3])

        def __call__(self) -> ObjectView:
            return _view()

        def method(self) -> int:
            return 1

    program = Program()
    out = process.run("p = movable.position\nv = movable()\ns = movable", {"movable": program})
    np.testing.assert_array_equal(out["p"], [1, 2, 3])
    assert out["v"].name == "mug" and out["s"] is program
    with pytest.raises(SandboxError, match="method"):
        process.run("f = movable.method", {"movable": program})
    with pytest.raises(SandboxError, match="refused"):
        process.run("movable.position = 1", {"movable": program})


def test_exceptions_keep_type_and_message(process: Sandbox, api: LMPAPI) -> None:
    for code, kind in [("x = undefined", NameError), ("x = [1][3]", IndexError),
                       ("x = {}['k']", KeyError), ("import os", SandboxError),
                       ("x = (", SyntaxError)]:
        with pytest.raises(kind) as isolated:
            process.run(code, {})
        with pytest.raises(kind) as inline:
            Sandbox().run(code, {})
        assert type(isolated.value) is type(inline.value)
        assert str(isolated.value) == str(inline.value)
    with pytest.raises(UnknownObjectError) as unknown:
        process.run("o = detect('teapot')", dict(api.namespace()))
    assert unknown.value.name == "teapot" and "blue block" in unknown.value.known
    assert "blue block" in str(unknown.value)


def test_a_nested_callback_that_raises_propagates_as_itself(process: Sandbox) -> None:
    raised: list[BaseException] = []

    def inner_lmp(query: str) -> Any:
        with suspend_time_limit():
            try:
                return process.run("x = 1 / 0", {})
            except ZeroDivisionError as exc:
                raised.append(exc)
                raise

    def outer_lmp(query: str) -> Any:
        with suspend_time_limit():
            return process.run("y = inner(q)\nret_val = y['x']", {"inner": inner_lmp, "q": query})

    assert process.run("z = inner_ok('a')", {"inner_ok": lambda q: process.run(
        "v = 2 * 3", {})["v"]})["z"] == 6
    with pytest.raises(ZeroDivisionError) as info:
        process.run("r = outer('q')", {"outer": outer_lmp})
    assert info.value is raised[0]


def test_an_endless_loop_ends_within_the_limit(process: Sandbox) -> None:
    start = time.monotonic()
    with pytest.raises(SandboxError, match="time limit"):
        process.run("while True:\n    pass", {})
    assert time.monotonic() - start < process.config.time_limit_s + 1.0
    assert process.run("y = 1", {})["y"] == 1


def test_a_call_stuck_in_c_is_killed_by_the_parent() -> None:
    sandbox = _escaped(time_limit_s=0.5)
    sandbox.run("y = 1", {})  # the worker is up
    start = time.monotonic()
    with pytest.raises(SandboxError, match="time limit"):
        sandbox.run("import time\ntime.sleep(60)", {})
    assert time.monotonic() - start < 0.5 + 1.0
    assert sandbox.run("y = 2", {})["y"] == 2
    sandbox.close()


def test_memory_above_the_limit_is_a_sandbox_error_and_the_next_run_works() -> None:
    sandbox = Sandbox(SandboxConfig(isolation="process", memory_limit_mb=768,
                                    max_elements=400_000_000))
    with pytest.raises(SandboxError, match="memory_limit_mb=768"):
        sandbox.run("a = np.ones(300_000_000)", {})  # 2.4 GB
    assert sandbox.run("a = np.ones(1000).sum()", {})["a"] == 1000
    sandbox.close()


def test_file_writes_are_refused_even_past_restricted_python(tmp_path: Path) -> None:
    sandbox = _escaped()
    target = tmp_path / "out.txt"
    target.write_text("kept")
    for path in (str(target), "relative.txt"):
        code = f"with open({path!r}, 'a') as f:\n    f.write('x' * 10)\n    f.flush()"
        with pytest.raises(OSError, match="File too large"):
            sandbox.run(code, {})
    assert target.read_text() == "kept"
    out = sandbox.run(FD_CODE, {})
    assert Path(out["cwd"]).name.startswith("voxposer-sandbox-") and out["cwd"] != os.getcwd()
    # stdio on /dev/null, the two arenas, the pipe to the parent (and the listing itself)
    assert all(t is None or t == "/dev/null" or t.startswith(("/dev/shm/", "socket:"))
               for t in out["fds"].values()), out["fds"]
    sandbox.close()


def test_cpu_limit_stops_the_worker() -> None:
    sandbox = _escaped(cpu_limit_s=1, time_limit_s=20)
    with pytest.raises(SandboxError, match="CPU limit"):
        sandbox.run("while True:\n    pass", {})
    assert sandbox.run("y = 3", {})["y"] == 3
    sandbox.close()


def test_a_killed_or_crashed_worker_is_reported_and_replaced() -> None:
    sandbox = _escaped()
    sandbox.run("y = 1", {})
    first = sandbox.worker_pid
    assert first is not None
    with pytest.raises(SandboxError, match="SIGSEGV"):
        sandbox.run("import os, signal\nos.kill(os.getpid(), signal.SIGSEGV)", {})
    assert sandbox.run("y = 1", {})["y"] == 1
    second = sandbox.worker_pid
    assert second not in (None, first)
    with pytest.raises(SandboxError, match="SIGKILL"):
        sandbox.run("y = kill()", {"kill": lambda: os.kill(second, signal.SIGKILL)})
    sandbox.run("y = 1", {})
    idle = sandbox.worker_pid
    assert idle is not None
    os.kill(idle, signal.SIGKILL)
    _wait_until_gone(idle)
    assert sandbox.run("y = 4", {})["y"] == 4  # killed while idle: replaced silently
    assert sandbox.worker_pid != idle
    sandbox.close()


def _wait_until_gone(pid: int, timeout_s: float = 10.0) -> None:
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return
        time.sleep(0.01)


def test_config_validates_the_isolation_fields() -> None:
    with pytest.raises(ConfigError, match=r"isolation.*'inline', 'process'.*'thread'"):
        SandboxConfig(isolation="thread")  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="memory_limit_mb"):
        SandboxConfig(memory_limit_mb=10)
    with pytest.raises(ConfigError, match="cpu_limit_s"):
        SandboxConfig(cpu_limit_s=0)
    with pytest.raises(ConfigError, match="max_open_files"):
        SandboxConfig(max_open_files=2)
