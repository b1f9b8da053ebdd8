"""LLM latency of one full instruction (planner → composer → map LMPs) with the configured model.

Three fresh processes share one temporary cache directory:

* cold   — nothing cached: every program's few-shot prefix is evaluated (and saved to disk);
* warm   — prefix states restored from disk, response cache empty (every call reaches the model);
* cached — the same instruction again: every call answered by the sqlite response cache.

Each figure is the wall time of the instruction in that process, model loading included. The
backend is ``LLMConfig.from_env()`` (the default local model unless VOXPOSER_LLM_* say otherwise).
The instruction runs through :class:`voxposer.lmp.LMPRuntime` on the built-in tabletop scene;
``--mode requests`` instead sends each prompt file once with a representative query. The last
line is machine-readable.

    python benchmarks/llm_latency.py [--instruction "..."] [--mode runtime|requests]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from rich.console import Console
from rich.table import Table

from voxposer.lmp.backends import LLMBackend, LLMConfig, LLMRequest, LLMResponse, make_backend

DEFAULT_INSTRUCTION = "push the red block 10 cm to the left"
REQUEST_QUERIES = {  # --mode requests: one representative query per program
    "planner": DEFAULT_INSTRUCTION,
    "composer": "push the red block 10cm in the -y direction",
    "parse_query_obj": "red block",
    "get_affordance_map": "a point 10cm in the -y direction of the red block",
    "get_avoidance_map": "10cm away from the cabinet",
    "get_velocity_map": "normal speed",
    "get_rotation_map": "default rotation",
    "get_gripper_map": "open everywhere",
}


class _Meter(LLMBackend):
    """Passes requests through and records each call's program, tokens and prefix source."""

    def __init__(self, inner: LLMBackend) -> None:
        self.inner = inner
        self.name = inner.name
        self.calls: list[dict[str, object]] = []

    @property
    def model(self) -> str:
        return self.inner.model

    def complete(self, request: LLMRequest) -> LLMResponse:
        response = self.inner.complete(request)
        self.calls.append(
            {
                "lmp": request.prefix_id,
                "prompt_tokens": response.prompt_tokens,
                "completion_tokens": response.completion_tokens,
                "seconds": round(response.seconds, 2),
                "prefix": response.extra.get("prefix", "cached" if response.cached else "-"),
            }
        )
        return response

    def close(self) -> None:
        self.inner.close()


def _run_phase(mode: str, instruction: str, cache_dir: Path, response_cache: bool) -> dict:
    start = time.perf_counter()
    meter = _Meter(make_backend(LLMConfig.from_env(cache_dir=cache_dir, cache=response_cache)))
    error = None
    if mode == "runtime":
        from voxposer.errors import VoxPoserError
        from voxposer.lmp import LMPRuntime, make_tabletop_scene

        try:
            LMPRuntime(make_tabletop_scene(), meter).run(instruction)
        except VoxPoserError as exc:  # the model's code failed; the LLM time still counts
            error = f"{type(exc).__name__}: {str(exc)[:200]}"
    else:
        from voxposer.lmp.prompt import load_prompt

        for lmp, query in REQUEST_QUERIES.items():
            messages = load_prompt(lmp).messages(f"# Query: {query}")
            meter.complete(LLMRequest(messages=messages, max_tokens=256, prefix_id=lmp))
    seconds = time.perf_counter() - start
    meter.close()
    return {"seconds": seconds, "calls": meter.calls, "error": error}


def _spawn(phase: str, args: argparse.Namespace, cache_dir: Path) -> dict:
    cmd = [sys.executable, __file__, "--phase", phase, "--mode", args.mode,
           "--instruction", args.instruction, "--cache-dir", str(cache_dir)]  # fmt: skip
    out = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--instruction", default=DEFAULT_INSTRUCTION)
    parser.add_argument("--mode", choices=("runtime", "requests"), default="runtime")
    parser.add_argument("--phase", choices=("cold", "warm", "cached"), help=argparse.SUPPRESS)
    parser.add_argument("--cache-dir", type=Path, help="default: a fresh temporary directory")
    args = parser.parse_args()
    if args.phase:  # worker process
        result = _run_phase(args.mode, args.instruction, args.cache_dir, args.phase != "cold")
        sys.stdout.write(json.dumps(result) + "\n")
        return

    console = Console(stderr=True)
    with tempfile.TemporaryDirectory(prefix="voxposer-llm-bench-") as tmp:
        cache_dir = args.cache_dir or Path(tmp)
        results = {}
        for phase in ("cold", "warm", "cached"):
            console.print(f"[bold]{phase}[/] …")
            results[phase] = _spawn(phase, args, cache_dir)
        states = sum(f.stat().st_size for f in (cache_dir / "prefix-states").glob("*.kv"))
    table = Table(title=f"{args.mode}: {args.instruction!r}")
    for column in ("phase", "call", "lmp", "prompt tok", "gen tok", "s", "prefix"):
        table.add_column(column)
    for phase, result in results.items():
        for i, call in enumerate(result["calls"], 1):
            table.add_row(phase, str(i), str(call["lmp"]), str(call["prompt_tokens"]),
                          str(call["completion_tokens"]), str(call["seconds"]), str(call["prefix"]))  # fmt: skip
        if result["error"]:
            console.print(f"[yellow]{phase}: the instruction failed: {result['error']}")
    console.print(table)
    console.print(f"prefix states on disk: {states / 2**20:.0f} MiB; threads: {os.cpu_count()}")
    print(
        f"cold_s={results['cold']['seconds']:.1f} warm_s={results['warm']['seconds']:.1f} "
        f"cached_s={results['cached']['seconds']:.2f}"
    )


if __name__ == "__main__":
    main()
