"""``voxposer lmp "<query>" --lmp get_affordance_map``: try one LMP on a scene.

Prints the generated code (and every self-correction attempt) and a summary of the result, and
writes an HTML picture of the resulting value map over the scene (plotly). The scene is the fixed
tabletop box scene (:func:`~voxposer.lmp.scene.make_tabletop_scene`); composer/planner queries
run against a :class:`~voxposer.lmp.handoff.RecordingHandler` (no robot).
"""

from __future__ import annotations

import argparse
import logging
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.syntax import Syntax

from voxposer.cli.checks import check_int, check_llm_options, check_out_dir, check_text
from voxposer.cli.llm_options import add_llm_options, backend_from_args
from voxposer.errors import VoxPoserError
from voxposer.lmp.handoff import RecordingHandler
from voxposer.lmp.object_view import ObjectView
from voxposer.lmp.registry import LMP_SPECS, LMPConfig, get_spec
from voxposer.lmp.runtime import LMPRuntime
from voxposer.lmp.scene import BoxScene, make_tabletop_scene
from voxposer.lmp.transcript import Transcript

logger = logging.getLogger(__name__)
console = Console(stderr=True)
_MAX_POINTS = 20_000


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Register the ``lmp`` command."""
    parser = subparsers.add_parser(
        "lmp", help="run one language model program on the tabletop scene; show code and map",
        description=__doc__.splitlines()[0])
    parser.add_argument("query", help='the query, e.g. "a point 5cm above the blue block"')
    parser.add_argument("--lmp", default="get_affordance_map", choices=list(LMP_SPECS),
                        help="which LMP to run (default: get_affordance_map)")
    parser.add_argument("--out", type=Path, default=Path("lmp_out"),
                        help="output directory for map.html and transcript.jsonl")
    parser.add_argument("--max-attempts", type=int, default=3,
                        help="LLM calls per query including self-correction")
    add_llm_options(parser)
    parser.set_defaults(func=run, check=check_args)
    return parser


def check_args(args: argparse.Namespace) -> None:
    """Refuse an empty query, ``--max-attempts`` outside [1, 10], an ``--out`` that is a file
    and unusable LLM options, before any model is loaded."""
    check_text(args.query, "query", "a point 5cm above the blue block")
    check_int(args.max_attempts, "--max-attempts", 1, 10)
    check_out_dir(args.out)
    check_llm_options(args, args.llm)


def run(args: argparse.Namespace) -> int:
    """Run the command; returns the exit status (0 ok, 1 the program failed)."""
    spec = get_spec(args.lmp)
    scene = make_tabletop_scene()
    args.out.mkdir(parents=True, exist_ok=True)
    transcript = Transcript(args.out / "transcript.jsonl")
    executor = RecordingHandler()
    try:
        backend = backend_from_args(args)
        runtime = LMPRuntime(scene, backend, executor, LMPConfig(max_attempts=args.max_attempts),
                             transcript)
        with console.status(f"{args.lmp}({args.query!r})…"):
            value = runtime.query(args.lmp, args.query)
    except VoxPoserError as exc:
        _show_code(transcript)
        console.print(f"[red]error:[/red] {exc}")
        return 1
    _show_code(transcript)
    if spec.role == "map":
        _summarize_map(spec.map_kind or "", value, scene)
        out = write_map_html(args.out / "map.html", value, scene, spec.map_kind or "",
                             f"{args.lmp}({args.query!r})")
        console.print(f"wrote [bold]{out}[/bold]")
    elif isinstance(value, ObjectView):
        console.print(f"object [bold]{value.name}[/bold] at voxel {value.position.tolist()} "
                      f"({np.round(value.position_world, 3).tolist()} m)")
    for k, done in enumerate(executor.evaluated):
        console.print(f"execute #{k + 1} ({executor.requests[k].subtask!r}): movable "
                      f"{done['movable'].name}")
        for name, arr in done.items():
            if name != "movable":
                _summarize_map(name.removesuffix("_map"), arr, scene)
    console.print(f"LLM calls: {runtime.llm_calls}; transcript: {args.out / 'transcript.jsonl'}")
    return 0


def _show_code(transcript: Transcript) -> None:
    for event in transcript.events:
        if event["event"] == "exec" and not event["replay"]:
            status = "ok" if event["ok"] else f"[red]{event['error']}[/red]"
            console.print(f"[bold]{event['lmp']}[/bold]({event['query']!r}) attempt "
                          f"{event['attempt']}: {status}")
            console.print(Syntax(event["code"], "python", theme="ansi_dark"))


def _changed(kind: str, value: np.ndarray) -> np.ndarray:
    """Voxels where a map differs from its neutral value, bool of shape grid.shape."""
    if kind == "rotation":  # voxels not holding the most common orientation
        flat = value.reshape(-1, 4)
        common = flat[0]
        return np.any(np.abs(value - common) > 1e-3, axis=-1)
    if kind == "velocity":
        return value != 1.0
    if kind == "gripper":
        return value > 0.5
    return value > 0


def _summarize_map(kind: str, value: np.ndarray, scene: BoxScene) -> None:
    arr = np.asarray(value)
    if kind == "rotation":
        console.print(f"rotation map: quaternion at the centre voxel "
                      f"{np.round(arr[tuple(np.asarray(arr.shape[:3]) // 2)], 3).tolist()}")
        return
    mask = _changed(kind, arr)
    count = int(mask.sum())
    line = f"{kind} map: {count} voxel(s) set, values {arr.min():.3g}..{arr.max():.3g}"
    if count and kind == "affordance":
        best = np.unravel_index(int(np.argmax(arr)), arr.shape)
        line += (f"; max at voxel {list(map(int, best))} = "
                 f"{np.round(scene.grid.voxel_to_world(np.array(best)), 3).tolist()} m")
    console.print(line)


def write_map_html(path: Path, value: np.ndarray, scene: BoxScene, kind: str, title: str) -> Path:
    """A self-contained plotly HTML of the map's non-neutral voxels over the scene's objects."""
    import plotly.graph_objects as go

    grid = scene.grid
    traces = []
    for name in scene.object_names:
        if name == "table":
            continue
        box = scene.box(name)
        corners = np.array([[x, y, z] for x in (box.lo[0], box.hi[0]) for y in (box.lo[1], box.hi[1])
                            for z in (box.lo[2], box.hi[2])])
        traces.append(go.Mesh3d(x=corners[:, 0], y=corners[:, 1], z=corners[:, 2],
                                alphahull=0, opacity=0.35, name=name, hovertext=name))
    mask = _changed(kind, np.asarray(value))
    idx = np.argwhere(mask)
    if len(idx) > _MAX_POINTS:
        idx = idx[np.linspace(0, len(idx) - 1, _MAX_POINTS).astype(int)]
    if len(idx):
        xyz = grid.voxel_to_world(idx)
        colour = (np.asarray(value)[tuple(idx.T)] if kind != "rotation" else idx[:, 2])
        traces.append(go.Scatter3d(x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2], mode="markers",
                                   marker={"size": 2, "color": colour, "colorscale": "Viridis",
                                           "colorbar": {"title": kind}}, name=f"{kind} map"))
    fig = go.Figure(traces)
    lo, hi = grid.bounds_min, grid.bounds_max
    fig.update_layout(title=title, scene={
        "xaxis": {"range": [lo[0], hi[0]], "title": "x (front +) [m]"},
        "yaxis": {"range": [lo[1], hi[1]], "title": "y (right +) [m]"},
        "zaxis": {"range": [lo[2], hi[2]], "title": "z (up +) [m]"}, "aspectmode": "cube"})
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.write_html(path, include_plotlyjs=True)
    return path
