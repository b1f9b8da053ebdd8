"""Accuracy of the language model programs: run each case's generated code, check its effect.

Usage::

    python benchmarks/lmp_accuracy.py                          # the default local model
    python benchmarks/lmp_accuracy.py --limit 20 --lmp get_affordance_map
    python benchmarks/lmp_accuracy.py --backend replay --recordings runs/lmp_rec.jsonl
    python benchmarks/lmp_accuracy.py --record runs/lmp_rec.jsonl   # record for later replay

Each case (``lmp_cases.py``) is executed on the fixed tabletop box scene; a case passes when its
result has the expected effect (target voxel within 1 cm, correct side of the object, avoided
region covering the object, speed scale in the right region…). Results go to a JSONL file as they
come; the last line printed is
``model=<name> seen_acc=<0..1> unseen_acc=<0..1> n=<cases> sec_per_query=<median>``.
"""

from __future__ import annotations

import argparse
import json
import logging
import statistics
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from rich.progress import Progress
from scipy.spatial.transform import Rotation

sys.path.insert(0, str(Path(__file__).parent))
from lmp_cases import all_cases
from voxposer.cli.llm_options import add_llm_options, backend_from_args
from voxposer.lmp.api import parse_side
from voxposer.lmp.handoff import RecordingHandler
from voxposer.lmp.registry import LMPConfig
from voxposer.lmp.runtime import LMPRuntime
from voxposer.lmp.scene import BoxScene, make_tabletop_scene
from voxposer.lmp.transcript import Transcript


def _vox(scene: BoxScene, point: np.ndarray) -> np.ndarray:
    return scene.grid.world_to_voxel(point, clip=True)


def _centre(scene: BoxScene, name: str) -> np.ndarray:
    box = scene.box(name)
    return (box.lo + box.hi) / 2


def _target(value: np.ndarray) -> np.ndarray:
    """The affordance target voxel: centroid of the maximal voxels."""
    idx = np.argwhere(value >= value.max() - 1e-6)
    return np.rint(idx.mean(axis=0)).astype(int)


def _cmp(op: str, got: float, want: float) -> bool:
    return {"eq": abs(got - want) < 0.02, "lt": got < want - 1e-3,
            "gt": got > want + 1e-3}[op]


def _shell(scene: BoxScene, centre: np.ndarray, cm: float) -> list[np.ndarray]:
    """Voxels ``cm`` away from ``centre`` [m] along ±x, ±y, +z (inside the grid)."""
    out = []
    for axis, sign in ((0, 1), (0, -1), (1, 1), (1, -1), (2, 1)):
        p = centre.copy()
        p[axis] += sign * cm / 100
        if scene.grid.contains(p):
            out.append(_vox(scene, p))
    return out


def check(scene: BoxScene, spec: dict[str, Any], value: Any) -> str | None:
    """None when ``value`` has the effect ``spec`` expects, else why not."""
    kind = spec["type"]
    if kind == "object":
        got = getattr(value, "name", None)
        return None if got == spec["name"] else f"got object {got!r}"
    arr = np.asarray(value)
    table = scene.box("table")
    if kind == "beside":
        box = scene.box(spec["object"])
        point = (box.lo + box.hi) / 2
        for axis, sign in parse_side(spec["side"]).items():
            point[axis] = (box.hi if sign > 0 else box.lo)[axis] + sign * spec["cm"] / 100
        err = np.abs(_target(arr) - _vox(scene, point))
        return None if np.all(err <= 1) else f"target off by {err.tolist()} voxels"
    if kind == "at_object":
        box = scene.box(spec["object"])  # over its centre, between its bottom and its top
        t, c = _target(arr), _vox(scene, _centre(scene, spec["object"]))
        lo, hi = _vox(scene, box.lo)[2] - 1, _vox(scene, box.hi)[2] + 1
        if spec.get("strict"):  # the centre itself (within a voxel)
            lo, hi = c[2] - 1, c[2] + 1
        ok = np.all(np.abs(t[:2] - c[:2]) <= 1) and lo <= t[2] <= hi
        return None if ok else f"target {t.tolist()} not at the object (centre {c.tolist()})"
    if kind == "table_region":
        t = scene.grid.voxel_to_world(_target(arr))
        for axis, sign in spec["signs"].items():
            lo, hi = table.lo[int(axis)], table.hi[int(axis)]
            frac = (t[int(axis)] - lo) / (hi - lo)
            if not (frac > 0.6 if sign > 0 else frac < 0.4):
                return f"target {np.round(t, 3).tolist()} m not on the expected side (axis {axis})"
        return None if t[2] < 0.3 else f"target {np.round(t, 3).tolist()} m too high"
    if kind == "avoid":
        c = _centre(scene, spec["object"])
        if arr[tuple(_vox(scene, c))] <= 0:
            return "object centre not avoided"
        r = spec["radius_cm"]
        if r is not None:
            if any(arr[tuple(v)] <= 0 for v in _shell(scene, c, r - 1.5)):
                return f"avoided region smaller than {r} cm"
            if any(arr[tuple(v)] > 0 for v in _shell(scene, c, r + 3)):
                return f"avoided region larger than {r} cm"
        return None
    if kind in ("speed_near", "speed_region"):
        if kind == "speed_near":
            c = _centre(scene, spec["object"])
            inside = [_vox(scene, c)] + _shell(scene, c, spec["radius_cm"] - 1.5)
            outside = _shell(scene, c, spec["radius_cm"] + 3)
        else:
            centre = (table.lo + table.hi) / 2
            pin, pout = centre.copy(), centre.copy()
            pin[2] = pout[2] = 0.2
            for axis, sign in spec["signs"].items():
                half = (table.hi - table.lo)[int(axis)] / 4
                pin[int(axis)] += sign * half
                pout[int(axis)] -= sign * half
            inside = [_vox(scene, pin)]
            outside = [_vox(scene, pout)] if spec["signs"] else []
        if not all(_cmp(spec["op"], float(arr[tuple(v)]), spec["value"]) for v in inside):
            return f"speed inside is {[float(arr[tuple(v)]) for v in inside][:2]}"
        if any(abs(float(arr[tuple(v)]) - 1.0) > 1e-3 for v in outside):
            return "speed changed outside the region"
        return None
    if kind == "gripper_all":
        return None if np.all(arr == spec["value"]) else "gripper map not uniform"
    if kind == "gripper_near":
        c = _centre(scene, spec["object"])
        if arr[tuple(_vox(scene, c))] != spec["inside"]:
            return f"gripper at the object is {arr[tuple(_vox(scene, c))]}"
        if spec["outside"] is not None:
            far = _shell(scene, c, (spec["radius_cm"] or 5) + 8)
            if any(arr[tuple(v)] != spec["outside"] for v in far):
                return "gripper away from the object is wrong"
        return None
    if kind == "approach":
        where = (_vox(scene, _centre(scene, spec["object"])) if spec["object"]
                 else np.asarray(scene.grid.shape) // 2)
        axis = Rotation.from_quat(arr[tuple(where)]).apply([0.0, 0.0, 1.0])
        want = np.asarray(spec["axis"], float)
        return None if axis @ want / np.linalg.norm(want) > 0.95 else \
            f"approach axis {np.round(axis, 2).tolist()}"
    raise ValueError(f"unknown check {kind!r}")


def run_case(runtime: LMPRuntime, case: dict[str, Any]) -> str | None:
    """Run one case; None when it passes, else the reason."""
    executor = runtime.executor
    assert isinstance(executor, RecordingHandler)
    executor.requests.clear()
    executor.evaluated.clear()
    value = runtime.query(case["lmp"], case["query"])
    spec = case["check"]
    if spec["type"] != "composer":
        return check(runtime.scene, spec, value)  # type: ignore[arg-type]
    if not executor.evaluated:
        return "composer did not call execute"
    done = executor.evaluated[-1]
    allowed = spec["movable"] if isinstance(spec["movable"], list) else [spec["movable"]]
    if done["movable"].name not in allowed:
        return f"movable is {done['movable'].name!r}"
    for name, sub in spec["maps"].items():
        if name not in done:
            return f"{name} missing"
        why = check(runtime.scene, sub, done[name])  # type: ignore[arg-type]
        if why:
            return f"{name}: {why}"
    return None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=int, default=None, help="run only the first N cases "
                        "(spread over all LMPs)")
    parser.add_argument("--lmp", action="append", default=None, help="only these LMPs")
    parser.add_argument("--split", choices=("seen", "unseen"), default=None)
    parser.add_argument("--max-attempts", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path("runs/lmp_accuracy.jsonl"))
    add_llm_options(parser)
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING)

    cases = [c for c in all_cases() if (args.lmp is None or c["lmp"] in args.lmp)
             and (args.split is None or c["split"] == args.split)]
    if args.limit is not None:  # round-robin over LMPs so a quick run touches each
        groups: dict[str, list[dict[str, Any]]] = {}
        for c in cases:
            groups.setdefault(c["lmp"], []).append(c)
        order = [g[i] for i in range(max(map(len, groups.values()))) for g in groups.values()
                 if i < len(g)]
        cases = order[: args.limit]
    backend = backend_from_args(args)
    runtime = LMPRuntime(make_tabletop_scene(), backend, RecordingHandler(),
                         LMPConfig(max_attempts=args.max_attempts), Transcript())
    args.out.parent.mkdir(parents=True, exist_ok=True)
    results: list[dict[str, Any]] = []
    with args.out.open("w", encoding="utf-8") as fh, Progress() as progress:
        task = progress.add_task("LMP cases", total=len(cases))
        for case in cases:
            start, first_event = time.monotonic(), len(runtime.transcript.events)
            try:
                why = run_case(runtime, case)
            except Exception as exc:
                why = f"{type(exc).__name__}: {exc}"
            seconds = time.monotonic() - start
            codes = [e["code"] for e in runtime.transcript.events[first_event:]
                     if e["event"] == "exec" and not e["replay"]]
            row = {**case, "ok": why is None, "why": why, "seconds": round(seconds, 3),
                   "code": codes}
            results.append(row)
            fh.write(json.dumps(row) + "\n")
            fh.flush()
            progress.advance(task)

    def acc(split: str) -> float:
        rows = [r for r in results if r["split"] == split]
        return sum(r["ok"] for r in rows) / len(rows) if rows else float("nan")

    for lmp in dict.fromkeys(r["lmp"] for r in results):
        rows = [r for r in results if r["lmp"] == lmp]
        print(f"{lmp}: {sum(r['ok'] for r in rows)}/{len(rows)}", file=sys.stderr)
    median = statistics.median(r["seconds"] for r in results) if results else 0.0
    print(f"model={backend.model} seen_acc={acc('seen'):.3f} unseen_acc={acc('unseen'):.3f} "
          f"n={len(results)} sec_per_query={median:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
