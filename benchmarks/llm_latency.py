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

``--mode suite`` times a set of one- and multi-sub-task instructions (``SUITE``) warm: one
process runs them all to evaluate every prefix they use (cold, not timed), then a fresh process
with those prefix states on disk and no response cache runs them again; per instruction it reports the seconds spent
in the model (the sum of its calls), the calls, the sub-tasks (composer calls) and seconds per
sub-task, then median and max, and the process's peak resident memory.

``--retrieved K`` sets how many example-bank examples each program gets per query
(``LMPConfig.retrieved_examples``; default: the config's), so the cost of examples chosen per
query is measured on one machine against ``--retrieved 0``. ``--context-mib 0`` turns off keeping
the model state after those examples (``LLMConfig.context_cache_mib``): every call evaluates
them; ``--batch`` generates a composer program's map calls together instead of one after another
(``LMPConfig.batch_map_calls``). In the suite's warm process kept states carry over from one instruction to the next, as in
a benchmark worker; ``context_kept`` counts the calls that found theirs kept.

    python benchmarks/llm_latency.py [--instruction "..."] [--mode runtime|requests|suite]
        [--retrieved K] [--context-mib MIB] [--batch]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

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


SUITE = (  # (instruction, sub-tasks it holds)
    ("move to the top of the blue block while staying away from the green block", 1),
    ("push the red block 10 cm to the left", 1),
    ("open the top drawer", 1),
    ("move to the back left corner of the table", 1),
    ("grasp the yellow block", 1),
    ("move 10cm above the pink block", 1),
    ("push the green block to the front side of the table", 1),
    ("move to the right side of the table at a quarter of the speed", 1),
    ("close the middle drawer", 1),
    ("hover 10 cm over the blue block, then go to the back right corner of the table", 2),
    ("push the red block to the left side of the table and then move away from it", 2),
    ("grasp the green block, then drop it at the front left corner of the table", 2),
)


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
        return self._meter(request, self.inner.complete(request))

    def complete_many(self, requests: Sequence[LLMRequest]) -> list[LLMResponse]:
        responses = self.inner.complete_many(requests)
        return [self._meter(q, r) for q, r in zip(requests, responses, strict=True)]

    def _meter(self, request: LLMRequest, response: LLMResponse) -> LLMResponse:
        self.calls.append(
            {
                "lmp": request.prefix_id,
                "prompt_tokens": response.prompt_tokens,
                "completion_tokens": response.completion_tokens,
                "seconds": round(response.seconds, 2),
                "prefix": response.extra.get("prefix", "cached" if response.cached else "-"),
                "context": response.extra.get("context", "-"),
            }
        )
        return response

    def close(self) -> None:
        self.inner.close()


def _config(retrieved: int | None, batch: bool = True) -> Any:
    from voxposer.lmp import LMPConfig

    config = LMPConfig(batch_map_calls=batch)
    return config if retrieved is None else replace(config, retrieved_examples=retrieved)


def _run_phase(mode: str, instruction: str, cache_dir: Path, response_cache: bool,
               retrieved: int | None = None, batch: bool = True) -> dict:
    start = time.perf_counter()
    meter = _Meter(make_backend(LLMConfig.from_env(cache_dir=cache_dir, cache=response_cache)))
    error = None
    if mode == "runtime":
        from voxposer.errors import VoxPoserError
        from voxposer.lmp import LMPRuntime, make_tabletop_scene

        try:
            LMPRuntime(make_tabletop_scene(), meter, config=_config(retrieved, batch)).run(
                instruction)
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


def _run_suite(cache_dir: Path, retrieved: int | None = None, batch: bool = True) -> dict:
    """Every ``SUITE`` instruction in this process, warm (prefix states from ``cache_dir``, no
    response cache): per instruction its calls, LLM seconds and composer calls."""
    from voxposer.errors import VoxPoserError
    from voxposer.lmp import LMPRuntime, make_tabletop_scene

    meter = _Meter(make_backend(LLMConfig.from_env(cache_dir=cache_dir, cache=False)))
    rows, per_call = [], []
    for instruction, _ in SUITE:
        meter.calls = []
        error = None
        try:
            LMPRuntime(make_tabletop_scene(), meter, config=_config(retrieved, batch)).run(
                instruction)
        except VoxPoserError as exc:
            error = f"{type(exc).__name__}: {str(exc)[:120]}"
        rows.append({"instruction": instruction, "calls": len(meter.calls),
                     "composer_calls": sum(c["lmp"] == "composer"
                                           or str(c["lmp"]).startswith("composer~")
                                           for c in meter.calls),
                     "llm_s": sum(float(c["seconds"]) for c in meter.calls),
                     "prompt_tokens": sum(int(c["prompt_tokens"] or 0) for c in meter.calls),
                     "completion_tokens": sum(int(c["completion_tokens"] or 0)
                                              for c in meter.calls),
                     "error": error})
        per_call += meter.calls
    meter.close()
    peak_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KiB on Linux
    return {"rows": rows, "calls": per_call, "peak_rss_mb": peak_kb / 1024}


def _suite(args: argparse.Namespace, console: Console, cache_dir: Path) -> None:
    if not args.warm_only:
        console.print(f"[bold]cold[/]: {len(SUITE)} instructions (prefix states, not timed) …")
        _spawn("suite", args, cache_dir)
    console.print(f"[bold]warm[/]: {len(SUITE)} instructions …")
    result = _spawn("suite", args, cache_dir)
    table = Table(title=f"warm LLM time per instruction, {os.cpu_count()} CPU cores")
    for column in ("instruction", "sub-tasks", "calls", "gen tok", "LLM s", "s per sub-task",
                   "error"):
        table.add_column(column)
    single, per_subtask, calls = [], [], []
    for row, (_, subtasks) in zip(result["rows"], SUITE, strict=True):
        per = row["llm_s"] / subtasks
        (single if subtasks == 1 else per_subtask).append(row["llm_s"] if subtasks == 1 else per)
        calls.append(row["calls"])
        table.add_row(row["instruction"], str(subtasks), str(row["calls"]),
                      str(row["completion_tokens"]), f"{row['llm_s']:.1f}", f"{per:.1f}",
                      row["error"] or "")
    console.print(table)
    by_lmp: dict[str, list[dict]] = {}
    for call in result["calls"]:
        by_lmp.setdefault(str(call["lmp"]).split("~")[0], []).append(call)
    lmps = Table(title="per program (all calls of the suite)")
    for column in ("program", "calls", "median gen tok", "median s", "prefix sources",
                   "examples kept / evaluated"):
        lmps.add_column(column)
    for name, group in sorted(by_lmp.items()):
        sources = sorted({str(c["prefix"]) for c in group})
        kept = sum(c.get("context") in ("live", "memory") for c in group)
        lmps.add_row(name, str(len(group)),
                     f"{statistics.median(int(c['completion_tokens'] or 0) for c in group):g}",
                     f"{statistics.median(float(c['seconds']) for c in group):.1f}",
                     ", ".join(sources),
                     f"{kept} / {sum(c.get('context') == 'evaluated' for c in group)}")
    console.print(lmps)
    generated = sum(r["completion_tokens"] for r in result["rows"])
    context_kept = sum(c.get("context") in ("live", "memory") for c in result["calls"])
    console.print(f"{generated} tokens generated in {sum(r['llm_s'] for r in result['rows']):.0f} "
                  f"s of model time over {sum(calls)} calls")
    print(f"retrieved={args.retrieved if args.retrieved is not None else 'default'} "
          f"batch={'on' if args.batch else 'off'} "
          f"context_mib={os.environ.get('VOXPOSER_LLM_CONTEXT_CACHE_MIB', 'default')} "
          f"one_subtask_median_s={statistics.median(single):.1f} "
          f"one_subtask_max_s={max(single):.1f} "
          f"multi_per_subtask_median_s={statistics.median(per_subtask):.1f} "
          f"multi_per_subtask_max_s={max(per_subtask):.1f} "
          f"calls_median={statistics.median(calls):g} peak_rss_mb={result['peak_rss_mb']:.0f} "
          f"context_kept={context_kept}/{len(result['calls'])}")


def _spawn(phase: str, args: argparse.Namespace, cache_dir: Path) -> dict:
    cmd = [sys.executable, __file__, "--phase", phase, "--mode", args.mode,
           "--instruction", args.instruction, "--cache-dir", str(cache_dir)]  # fmt: skip
    if args.retrieved is not None:
        cmd += ["--retrieved", str(args.retrieved)]
    if args.batch:
        cmd += ["--batch"]
    out = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--instruction", default=DEFAULT_INSTRUCTION)
    parser.add_argument("--mode", choices=("runtime", "requests", "suite"), default="runtime")
    parser.add_argument("--phase", choices=("cold", "warm", "cached", "suite"),
                        help=argparse.SUPPRESS)
    parser.add_argument("--cache-dir", type=Path, help="default: a fresh temporary directory")
    parser.add_argument("--warm-only", action="store_true",
                        help="--mode suite: skip the cold pass (--cache-dir already holds the "
                             "prefix states of every program the suite uses)")
    parser.add_argument("--retrieved", type=int, default=None,
                        help="bank examples per query (default: LMPConfig's)")
    parser.add_argument("--context-mib", type=int, default=None,
                        help="memory for states after each query's retrieved examples [MiB] "
                             "(VOXPOSER_LLM_CONTEXT_CACHE_MIB; 0 = evaluate them every call)")
    parser.add_argument("--batch", action="store_true",
                        help="a composer's map calls generated together (LMPConfig."
                             "batch_map_calls=True) instead of one after another")
    args = parser.parse_args()
    if args.context_mib is not None:  # read by LLMConfig.from_env in the worker processes
        os.environ["VOXPOSER_LLM_CONTEXT_CACHE_MIB"] = str(args.context_mib)
    if args.phase == "suite":  # worker process of --mode suite
        sys.stdout.write(json.dumps(_run_suite(args.cache_dir, args.retrieved,
                                               args.batch)) + "\n")
        return
    if args.phase:  # worker process
        mode = "runtime" if args.mode == "suite" else args.mode
        result = _run_phase(mode, args.instruction, args.cache_dir, args.phase != "cold",
                            args.retrieved, args.batch)
        sys.stdout.write(json.dumps(result) + "\n")
        return

    console = Console(stderr=True)
    with tempfile.TemporaryDirectory(prefix="voxposer-llm-bench-") as tmp:
        cache_dir = args.cache_dir or Path(tmp)
        if args.mode == "suite":
            _suite(args, console, cache_dir)
            return
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
