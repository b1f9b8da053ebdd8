"""A self-contained HTML picture of a plan: cost map, scene points, start, target and path."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
import plotly.graph_objects as go
from numpy.typing import NDArray

from voxposer.planning.planner import Plan

_MAX_VOLUME_SIDE = 32
_MAX_POINTS = 20_000


def _volume_trace(plan: Plan) -> go.Volume:
    """The cost map as a translucent volume, subsampled to at most 32 voxels a side."""
    cmap = plan.cost_map
    step = max(1, int(np.ceil(max(cmap.grid.shape) / _MAX_VOLUME_SIDE)))
    cost = cmap.cost[::step, ::step, ::step].astype(np.float64)
    idx = np.stack(
        np.meshgrid(*[np.arange(0, n, step) for n in cmap.grid.shape], indexing="ij"), -1
    )
    xyz = cmap.grid.voxel_to_world(idx.reshape(-1, 3))
    return go.Volume(
        x=xyz[:, 0],
        y=xyz[:, 1],
        z=xyz[:, 2],
        value=cost.ravel(),
        isomin=0.0,
        isomax=float(cost.max()),
        opacity=0.12,
        surface_count=10,
        colorscale="Viridis",
        reversescale=True,
        colorbar={"title": "cost", "x": -0.05, "len": 0.6},
        name="cost map",
        showlegend=True,
    )


def _points(pts: NDArray[np.float64], name: str, *, size: float, color: str,
            symbol: str = "circle") -> go.Scatter3d:
    """Markers at ``pts`` [m], shape (N, 3)."""
    return go.Scatter3d(x=pts[:, 0], y=pts[:, 1], z=pts[:, 2], mode="markers",
                        marker={"size": size, "color": color, "symbol": symbol}, name=name)


def plan_figure(
    plan: Plan,
    scene_points: NDArray[np.float64] | None = None,
    other_paths: Mapping[str, NDArray[np.float64]] | None = None,
    title: str = "VoxPoser plan",
) -> go.Figure:
    """Plotly figure of a plan.

    Args:
        plan: the plan to draw (its cost map, trajectory, start and target).
        scene_points: scene point cloud [m], shape (N, 3); subsampled to 20k points.
        other_paths: more paths to overlay (e.g. the greedy baseline), name → (M, 3) [m].
        title: figure title.
    """
    traces: list[go.BaseTraceType] = [_volume_trace(plan)]
    if scene_points is not None and len(scene_points):
        pts = np.asarray(scene_points)
        if len(pts) > _MAX_POINTS:
            pts = pts[np.linspace(0, len(pts) - 1, _MAX_POINTS).astype(int)]
        traces.append(_points(pts, "scene points", size=1.5, color="rgba(90,90,90,0.5)"))
    pos = plan.trajectory.positions
    traces.append(go.Scatter3d(
        x=pos[:, 0], y=pos[:, 1], z=pos[:, 2], mode="lines+markers",
        line={"width": 6, "color": "royalblue"}, marker={"size": 2},
        name=f"{plan.method} path ({'reached' if plan.reached else 'stalled'})"))
    for name, path in (other_paths or {}).items():
        q = np.asarray(path)
        traces.append(go.Scatter3d(
            x=q[:, 0], y=q[:, 1], z=q[:, 2], mode="lines",
            line={"width": 5, "color": "darkorange", "dash": "dash"}, name=name))
    start = plan.cost_map.start
    targets = plan.cost_map.fine_grid.voxel_to_world(plan.cost_map.fine_targets)
    traces.append(_points(start[None, :], "start", size=8, color="limegreen", symbol="diamond"))
    targets = targets[np.linspace(0, len(targets) - 1, min(len(targets), 2000)).astype(int)]
    traces.append(_points(targets, "affordance target", size=5, color="crimson"))
    lo, hi = plan.cost_map.fine_grid.bounds_min, plan.cost_map.fine_grid.bounds_max
    fig = go.Figure(data=traces)
    fig.update_layout(
        title=title,
        scene={
            "xaxis": {"title": "x [m] (front +)", "range": [lo[0], hi[0]]},
            "yaxis": {"title": "y [m] (right +)", "range": [lo[1], hi[1]]},
            "zaxis": {"title": "z [m] (up +)", "range": [lo[2], hi[2]]},
            "aspectmode": "cube",
        },
        legend={"itemsizing": "constant"},
        margin={"l": 0, "r": 0, "t": 40, "b": 0},
    )
    return fig


def write_plan_html(path: str | Path, figure: go.Figure) -> Path:
    """Write ``figure`` as one self-contained HTML file (plotly.js embedded, works offline)."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    figure.write_html(out, include_plotlyjs=True, full_html=True)
    return out
