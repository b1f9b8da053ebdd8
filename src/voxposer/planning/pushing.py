"""Planar pushing: a heuristic dynamics model and random-shooting MPC (paper Sec. 4 "Dynamics Model").

When the entity of interest is an object (or an object part such as a drawer), the planner plans
a path for the object's centre; this module chooses how to push it along that path. A push is
parametrised by a contact point on the object, a push direction in the table plane and a push
distance. The dynamics model is the paper's heuristic: the object's points translate along the
push direction by the push distance. Random shooting samples thousands of pushes at once
(vectorised: no Python loop per sample), predicts where each leaves the object, and keeps the one
whose predicted position is closest to a look-ahead point on the planned path, penalised by the
cost map, by predicted collisions and by the hand sweeping over an obstacle during the stroke
(the hand lies across the push for a flat two-finger contact, or along it where across would
sweep through an obstacle).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, QhullError

from voxposer.errors import ConfigError, PlanningError
from voxposer.planning.push_clearance import add_hand_sweep
from voxposer.planning.trajectory import resample
from voxposer.valuemaps.cost import CostMap


@dataclass(frozen=True)
class PushConfig:
    """Random-shooting MPC parameters.

    Attributes:
        n_samples: pushes sampled per MPC step.
        min_distance_m, max_distance_m: push distance range [m].
        lookahead_m: how far along the planned path a push aims [m].
        contact_height_m: contact height above the object's lowest point [m] (of the
            fingertip centre; the closed fingers' flat faces then touch the object from 1.2 cm
            up, and the hand's underside, ``hand_underside_m`` higher, just clears a 5 cm block:
            at 2 cm it swept into the pushed block's neighbours; at 3 cm the fingers rode up
            over a block that resisted).
        lateral_fraction: contact points spread over this fraction of the object's half-width.
        cost_weight: weight of the cost map at the predicted position (avoidance, detours) [m per cost unit].
        collision_weight: penalty per predicted object point inside an obstacle [m].
        hand_half_length_m, hand_half_width_m: the closed hand's footprint in the table plane
            [m] (Panda hand: ±0.105 m along the finger axis, ±0.033 m across it).
        hand_underside_m: height of the hand's underside above the fingertip centre (the
            contact point) [m].
        tool_collision_weight: penalty per hand-footprint sample inside an obstacle along the
            stroke [m].
        along_penalty_m: extra cost of pushing with the hand's long axis along the push (narrow
            finger contact, the block turns more easily) instead of across it (flat contact) [m].
    """

    n_samples: int = 10_000
    min_distance_m: float = 0.01
    max_distance_m: float = 0.08
    lookahead_m: float = 0.06
    contact_height_m: float = 0.025
    lateral_fraction: float = 0.5
    cost_weight: float = 0.02
    collision_weight: float = 0.05
    hand_half_length_m: float = 0.105
    hand_half_width_m: float = 0.033
    hand_underside_m: float = 0.027
    tool_collision_weight: float = 0.05
    along_penalty_m: float = 0.02

    def __post_init__(self) -> None:
        if self.n_samples < 1:
            raise ConfigError(f"PushConfig.n_samples must be >= 1; got {self.n_samples!r}")
        if not 0 < self.min_distance_m <= self.max_distance_m:
            raise ConfigError(
                "PushConfig needs 0 < min_distance_m <= max_distance_m; got "
                f"{self.min_distance_m!r}, {self.max_distance_m!r}"
            )
        if self.lookahead_m <= 0 or not 0 <= self.lateral_fraction <= 1:
            raise ConfigError(
                f"PushConfig.lookahead_m must be > 0 and lateral_fraction in [0, 1]; got "
                f"{self.lookahead_m!r}, {self.lateral_fraction!r}"
            )


class PushAction(NamedTuple):
    """The chosen push.

    Attributes:
        contact: contact point on the object's surface [m], shape (3,).
        direction: unit push direction in the table plane, shape (3,).
        distance: push distance [m].
        predicted_position: the object's predicted centre after the push [m], shape (3,).
        score: MPC objective of this push (lower is better) [m].
        hand_axis: unit direction in the table plane of the hand's long (finger) axis, shape
            (3,): across the push (flat contact) unless that sweeps the hand through an obstacle.
    """

    contact: NDArray[np.float64]
    direction: NDArray[np.float64]
    distance: float
    predicted_position: NDArray[np.float64]
    score: float
    hand_axis: NDArray[np.float64]


def translate_points(points: NDArray, directions: NDArray, distances: NDArray) -> NDArray:
    """The heuristic push dynamics: object points after pushes (batched).

    Args:
        points: object points [m], shape (P, 3).
        directions: unit push directions, shape (S, 3).
        distances: push distances [m], shape (S,).

    Returns:
        predicted points [m], shape (S, P, 3).
    """
    return points[None, :, :] + (directions * distances[:, None])[:, None, :]


def _lookahead_point(path: NDArray[np.float64], lookahead: float) -> NDArray[np.float64]:
    """The point ``lookahead`` metres along a polyline (its end if shorter)."""
    if len(path) < 2:
        return path[-1]
    dense = resample(path, 0.005)
    steps = np.linalg.norm(np.diff(dense, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(steps)])
    return dense[min(int(np.searchsorted(arc, lookahead)), len(dense) - 1)]


def _footprint(points: NDArray[np.float64], spacing: float = 0.01) -> NDArray[np.float64]:
    """The object's outline in the table plane: its 2-D convex hull, sampled every ``spacing`` [m].

    Returns points [m], shape (K, 3), at the height of the points' mean.
    """
    xy = points[:, :2]
    z = float(points[:, 2].mean())
    try:
        corners = xy[ConvexHull(xy).vertices]
    except (QhullError, ValueError):  # fewer than 3 points or all collinear
        corners = xy[[int(np.argmin(xy @ d)) for d in ((1, 0), (-1, 0), (0, 1), (0, -1))]]
    loop = np.vstack([corners, corners[:1]])
    ring = resample(np.column_stack([loop, np.full(len(loop), z)]), spacing)
    return ring[:-1] if len(ring) > 1 else ring


def random_shooting(
    object_points: NDArray[np.float64],
    path: NDArray[np.float64],
    rng: np.random.Generator,
    *,
    cost_map: CostMap | None = None,
    axis: NDArray[np.float64] | None = None,
    config: PushConfig | None = None,
) -> PushAction:
    """Choose a push that moves the object along ``path`` (random-shooting MPC, one step).

    Args:
        object_points: the object's observed points [m], shape (P, 3), P >= 1.
        path: planned path of the object's centre [m], shape (M, 3), starting at the object.
        rng: source of the samples.
        cost_map: if given, its cost at the predicted centre and its obstacles under the
            object's predicted outline are penalised.
        axis: if given (e.g. a drawer's sliding axis), pushes are restricted to ±axis.
        config: MPC parameters.

    Raises:
        PlanningError: no object points.
    """
    cfg = config or PushConfig()
    pts = np.asarray(object_points, dtype=np.float64).reshape(-1, 3)
    if len(pts) == 0:
        raise PlanningError("cannot push an object with no observed points")
    centre = pts.mean(axis=0)
    goal = _lookahead_point(np.asarray(path, dtype=np.float64), cfg.lookahead_m)
    n = cfg.n_samples

    if axis is not None:
        a = np.asarray(axis, dtype=np.float64)
        a = a / np.linalg.norm(a)
        directions = np.where(rng.random(n)[:, None] < 0.5, a, -a)
    else:
        theta = rng.uniform(-np.pi, np.pi, n)
        directions = np.stack([np.cos(theta), np.sin(theta), np.zeros(n)], axis=1)
    distances = rng.uniform(cfg.min_distance_m, cfg.max_distance_m, n)

    # contact: the object's extreme point opposite the push, shifted sideways, at push height
    ring = _footprint(pts) - centre  # (K, 3) outline in the table plane, K small
    depth = -(directions @ ring.T).min(axis=1)  # distance from centre to the rear face [m]
    side = np.stack([-directions[:, 1], directions[:, 0], np.zeros(n)], axis=1)
    half_width = np.abs(side @ ring.T).max(axis=1)
    lateral = rng.uniform(-1, 1, n) * cfg.lateral_fraction * half_width
    contacts = centre - directions * depth[:, None] + side * lateral[:, None]
    contacts[:, 2] = pts[:, 2].min() + cfg.contact_height_m

    predicted = centre + directions * distances[:, None]
    score = np.linalg.norm(predicted - goal, axis=1)
    if cost_map is not None:
        grid = cost_map.grid
        lo, res, top = grid.bounds_min, grid.resolution, np.asarray(grid.shape) - 1
        vox = np.clip(((predicted - lo) / res).astype(np.int64), 0, top)
        score += cfg.cost_weight * cost_map.cost[vox[:, 0], vox[:, 1], vox[:, 2]]
        probe = centre + ring  # the outline at the centre's height
        moved = translate_points(probe, directions, distances).reshape(-1, 3)
        mvox = np.clip(((moved - lo) / res).astype(np.int64), 0, top)
        hits = cost_map.obstacles[mvox[:, 0], mvox[:, 1], mvox[:, 2]].reshape(n, -1).sum(axis=1)
        score += cfg.collision_weight * hits
    along = np.zeros(n, dtype=bool)
    if cost_map is not None and axis is None:  # parts are pushed hand-first, not top-down
        score, along = add_hand_sweep(score, contacts, directions, distances, side, cost_map, cfg)
    best = int(np.argmin(score))
    return PushAction(
        contact=contacts[best],
        direction=directions[best],
        distance=float(distances[best]),
        predicted_position=predicted[best],
        score=float(score[best]),
        hand_axis=(directions if along[best] else side)[best],
    )


def push_waypoints(
    action: PushAction,
    *,
    approach_clearance_m: float = 0.04,
    lift_height_m: float = 0.08,
    tool_radius_m: float = 0.01,
) -> NDArray[np.float64]:
    """End-effector positions [m], shape (5, 3), of the pushing primitive for ``action``.

    Above the pre-contact point → down behind the contact point → along the push direction until
    the object has moved the push distance → back a little → up. The gripper stays closed.
    ``tool_radius_m`` is the half-thickness of the closed fingers along the push: the tool's
    centre stops that far short of the contact point's final position.
    """
    behind = action.contact - action.direction * (approach_clearance_m + tool_radius_m)
    end = action.contact + action.direction * (action.distance - tool_radius_m)
    up = np.array([0.0, 0.0, lift_height_m])
    retreat = end - action.direction * 0.02
    return np.stack([behind + up, behind, end, retreat, retreat + up])
