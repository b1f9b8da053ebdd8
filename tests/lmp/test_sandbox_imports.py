"""numpy's own lazy imports work under the sandbox's builtins; generated code still imports
nothing. Deep recursion is reported as a SandboxError."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

from voxposer.errors import SandboxError
from voxposer.lmp.sandbox import Sandbox, SandboxConfig

FRESH_PROCESS = textwrap.dedent("""
    from voxposer.errors import SandboxError
    from voxposer.lmp.sandbox import Sandbox

    sandbox = Sandbox()
    out = sandbox.run("a = np.zeros((10, 10, 10)); ret_val = float(a.sum())", {})
    shown = sandbox.run("s = repr(np.arange(3)) + str(np.float64(0.5))", {})["s"]
    for code in ("import os", "from os import path", "__import__('os')"):
        try:
            sandbox.run(code, {})
        except SandboxError as exc:
            print("blocked", repr(code), "->", exc)
        else:
            raise SystemExit("not refused: " + code)
    print("ret_val", out["ret_val"], shown)
""")


def test_numpy_lazy_imports_work_in_a_fresh_process() -> None:
    """In a fresh process the first ``a.sum()`` makes numpy import ``numpy._core._methods``
    through the running frame's builtins — the sandbox's (it used to raise KeyError)."""
    done = subprocess.run([sys.executable, "-c", FRESH_PROCESS], capture_output=True, text=True,
                          timeout=300, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "ret_val 0.0 array([0, 1, 2])0.5" in done.stdout
    assert done.stdout.count("blocked") == 3


@pytest.fixture(scope="module")
def sandbox() -> Sandbox:
    return Sandbox(SandboxConfig(time_limit_s=0.5))


def test_the_import_hook_lets_only_numpy_and_scipy_through(sandbox: Sandbox) -> None:
    hook = sandbox.base_globals()["__builtins__"]["__import__"]
    assert hook("numpy._core._methods", None, None, ["_sum"], 0).__name__.startswith("numpy")
    for name, level in (("os", 0), ("subprocess", 0), ("numpyx", 0), ("numpy", 1)):
        with pytest.raises(SandboxError, match=rf"refused: importing '{name}'"):
            hook(name, None, None, (), level)


@pytest.mark.parametrize("code", [
    "def f(n):\n    return f(n + 1)\nf(0)",
    "def a(n):\n    return b(n)\ndef b(n):\n    return a(n + 1)\nx = a(0)",
    "f = lambda g, n: g(g, n + 1)\nf(f, 0)",
])
def test_deep_recursion_is_a_sandbox_error(sandbox: Sandbox, code: str) -> None:
    with pytest.raises(SandboxError, match=r"recursion limit: .*too deeply") as info:
        sandbox.run(code, {})
    assert isinstance(info.value.__cause__, RecursionError)
    # the tracer is back: the next endless loop still hits the time limit
    with pytest.raises(SandboxError, match="time limit"):
        sandbox.run("while True:\n    pass", {})
