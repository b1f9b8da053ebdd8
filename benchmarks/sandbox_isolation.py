"""Cost of one value-map program evaluation in the sandbox: inline vs process isolation.

The program is what ``get_affordance_map`` code does on every re-evaluation: it calls
``parse_query_obj`` (a nested program, ``ret_val = detect(...)``, run by the same sandbox as the
runtime's replay does), builds a 100 x 100 x 100 map, paints a sphere and a box, and returns it.
Every run is timed end to end (what the caller of ``Sandbox.run`` waits); the worker of process
isolation is started once before timing. Also timed: replacing a dead worker
(the median extra time of the first run after a kill).

Prints medians and 90th percentiles and ends with one machine-readable line:
``inline_ms=… inline_p90_ms=… inline_cpu_ms=… process_ms=… process_p90_ms=… process_cpu_ms=…
overhead_ms=… overhead_cpu_ms=… restart_ms=…`` (wall medians, p90s, CPU per evaluation; the CPU
figures hold up better than wall time on a loaded machine).
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import argparse
import signal
import time
from typing import Any

import numpy as np

from voxposer.lmp import make_tabletop_scene
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.sandbox import Sandbox, SandboxConfig, suspend_time_limit

MAP_PROGRAM = """
affordance_map = get_empty_affordance_map()
block = parse_query_obj('blue block')
x, y, z = block.position + cm2index(10, 'z')
set_voxel_by_radius(affordance_map, (x, y, z), 3, 1)
affordance_map[block.aabb[0][0]:block.aabb[1][0] + 1, block.aabb[0][1]:block.aabb[1][1] + 1,
               block.aabb[1][2]] = 0.5
ret_val = affordance_map
"""
OBJECT_PROGRAM = "ret_val = detect(query)"


def _variables(sandbox: Sandbox, api: LMPAPI) -> dict[str, Any]:
    """The map program's names: the scene API and a ``parse_query_obj`` that runs a nested
    object program in the same sandbox (like ``LMPRuntime``'s replay of cached code)."""
    base = dict(api.namespace())

    def parse_query_obj(query: str) -> Any:
        with suspend_time_limit():
            return sandbox.run(OBJECT_PROGRAM, {**base, "query": str(query)})["ret_val"]

    return {**base, "parse_query_obj": parse_query_obj}


def _cpu_s(pid: int | None) -> float:
    """CPU time [s] used so far by this process plus process ``pid`` (the worker), if any."""
    own = time.process_time()
    if pid is None:
        return own
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return own + (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _times_ms(sandbox: Sandbox, variables: dict[str, Any], runs: int, shape: tuple[int, ...]
              ) -> tuple[np.ndarray, float]:
    """Wall time of each of ``runs`` evaluations [ms], shape (runs,), and the mean CPU time
    of one (this process and the worker together) [ms]."""
    sandbox.run(MAP_PROGRAM, variables)  # warm: the worker is up, numpy paths are hot
    pid = sandbox.worker_pid
    cpu = _cpu_s(pid)
    out = []
    for _ in range(runs):
        start = time.perf_counter()
        result = sandbox.run(MAP_PROGRAM, variables)["ret_val"]
        out.append((time.perf_counter() - start) * 1000.0)
        if result.shape != shape or not np.any(result > 0):
            raise RuntimeError(f"unexpected map: shape {result.shape}, max {result.max()}")
    return np.asarray(out), (_cpu_s(pid) - cpu) * 1000.0 / runs


def _restart_ms(sandbox: Sandbox, repeats: int = 5) -> float:
    """Median time of a trivial run that first has to replace a killed worker [ms]."""
    out = []
    for _ in range(repeats):
        sandbox.run("y = 1", {})
        pid = sandbox.worker_pid
        if pid is None:
            raise RuntimeError("no worker after a run")
        os.kill(pid, signal.SIGKILL)
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline:
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                break
            time.sleep(0.005)
        start = time.perf_counter()
        sandbox.run("y = 1", {})
        out.append((time.perf_counter() - start) * 1000.0)
    return float(np.median(out))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=50, help="timed evaluations per mode")
    args = parser.parse_args()
    api = LMPAPI(make_tabletop_scene())
    figures: dict[str, float] = {}
    sandboxes = {mode: Sandbox(SandboxConfig(isolation=mode)) for mode in ("inline", "process")}
    for mode, sandbox in sandboxes.items():
        times, cpu = _times_ms(sandbox, _variables(sandbox, api), args.runs,
                               tuple(api.grid.shape))
        figures[f"{mode}_ms"] = float(np.median(times))
        figures[f"{mode}_p90_ms"] = float(np.percentile(times, 90))
        figures[f"{mode}_cpu_ms"] = cpu
        print(f"{mode:>7}: median {figures[f'{mode}_ms']:.2f} ms, p90 "
              f"{figures[f'{mode}_p90_ms']:.2f} ms over {args.runs} evaluations; CPU "
              f"{cpu:.2f} ms each (parent + worker)")
    figures["overhead_ms"] = figures["process_ms"] - figures["inline_ms"]
    figures["overhead_cpu_ms"] = figures["process_cpu_ms"] - figures["inline_cpu_ms"]
    figures["restart_ms"] = _restart_ms(sandboxes["process"])
    print(f"process isolation adds {figures['overhead_ms']:.2f} ms per evaluation; replacing a "
          f"dead worker adds {figures['restart_ms']:.0f} ms to the next run")
    for sandbox in sandboxes.values():
        sandbox.close()
    print(" ".join(f"{k}={v:.2f}" for k, v in figures.items()))


if __name__ == "__main__":
    main()
