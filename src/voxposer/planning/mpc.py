"""Random-shooting MPC over any dynamics model (paper Sec. 4 "Dynamics Model").

When the entity of interest is an object (or an object part such as a drawer), the planner plans
a path for the object's centre; :func:`random_shooting` chooses how to push it along that path.
It samples thousands of pushes at once (vectorised: no Python loop per sample), predicts where
each leaves the object through a :class:`~voxposer.planning.dynamics.DynamicsModel` (default:
the paper's heuristic, :class:`~voxposer.planning.dynamics.TranslationPush`), and keeps the one
whose predicted position is closest to a look-ahead point on the planned path, penalised by the
cost map, by predicted collisions and by the hand sweeping over an obstacle during the stroke
(the hand lies across the push for a flat two-finger contact, or along it where across would
sweep through an obstacle).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import PlanningError
from voxposer.planning.dynamics import DynamicsModel, PushBatch, TranslationPush
from voxposer.planning.push_clearance import add_hand_sweep
from voxposer.planning.push_primitive import PushAction, PushConfig, footprint
from voxposer.planning.trajectory import resample
from voxposer.valuemaps.cost import CostMap

#: score added to a push like one the arm could not reach [m]: above any other sample's.
_REFUSED = 1e6


def lookahead_point(path: NDArray[np.float64], lookahead: float) -> NDArray[np.float64]:
    """The point ``lookahead`` metres along a polyline (its end if shorter)."""
    if len(path) < 2:
        return path[-1]
    dense = resample(path, 0.005)
    steps = np.linalg.norm(np.diff(dense, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(steps)])
    return dense[min(int(np.searchsorted(arc, lookahead)), len(dense) - 1)]


def sample_pushes(points: NDArray[np.float64], rng: np.random.Generator, config: PushConfig,
                  axis: NDArray[np.float64] | None = None
                  ) -> tuple[PushBatch, NDArray[np.float64], NDArray[np.float64]]:
    """``config.n_samples`` pushes of the object with ``points`` [m], shape (P, 3), P >= 1:
    random directions in the table plane (±``axis`` when given), distances in the configured
    range, contacts on the face opposite the push, shifted sideways, at push height.

    Returns:
        (the pushes, their sideways unit axes (S, 3), the object's outline relative to its
        centre (K, 3)).
    """
    cfg, n = config, config.n_samples
    centre = points.mean(axis=0)
    if axis is not None:
        a = np.asarray(axis, dtype=np.float64)
        a = a / np.linalg.norm(a)
        directions = np.where(rng.random(n)[:, None] < 0.5, a, -a)
    else:
        theta = rng.uniform(-np.pi, np.pi, n)
        directions = np.stack([np.cos(theta), np.sin(theta), np.zeros(n)], axis=1)
    distances = rng.uniform(cfg.min_distance_m, cfg.max_distance_m, n)
    # contact: the object's extreme point opposite the push, shifted sideways, at push height
    ring = footprint(points) - centre  # (K, 3) outline in the table plane, K small
    depth = -(directions @ ring.T).min(axis=1)  # distance from centre to the rear face [m]
    side = np.stack([-directions[:, 1], directions[:, 0], np.zeros(n)], axis=1)
    half_width = np.abs(side @ ring.T).max(axis=1)
    lateral = rng.uniform(-1, 1, n) * cfg.lateral_fraction * half_width
    contacts = centre - directions * depth[:, None] + side * lateral[:, None]
    contacts[:, 2] = points[:, 2].min() + cfg.contact_height_m
    return PushBatch(contacts, directions, distances), side, ring


def _outline_hits(points: NDArray[np.float64], cost_map: CostMap) -> NDArray[np.int64]:
    """Predicted outline points [m], shape (S, K, 3), inside the scene's obstacles, per sample,
    shape (S,). The scene's own voxels (``fine_obstacles``), not the planner's obstacles: those
    also hold the avoidance map's kept-out core and everything outside the object's layer,
    which the planned path of the object's *centre* keeps clear of (the centre is checked
    against them). An outline counted against them made every push along a path that skirts
    the core score worse than a 1 cm nudge, and the object stalled there."""
    vox = cost_map.fine_grid.world_to_voxel(points.reshape(-1, 3), clip=True)
    inside = cost_map.fine_obstacles[vox[:, 0], vox[:, 1], vox[:, 2]]
    return inside.reshape(points.shape[0], -1).sum(axis=1)


def random_shooting(
    object_points: NDArray[np.float64],
    path: NDArray[np.float64],
    rng: np.random.Generator,
    *,
    cost_map: CostMap | None = None,
    axis: NDArray[np.float64] | None = None,
    config: PushConfig | None = None,
    model: DynamicsModel | None = None,
    refused: NDArray[np.float64] | None = None,
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
        model: the dynamics model predictions come from (default: :class:`TranslationPush`).
        refused: unit push directions the arm could not carry out from here, shape (R, 3):
            pushes within ``config.refused_angle_deg`` of one are chosen only when no other
            sample is left.

    Raises:
        PlanningError: no object points.
    """
    cfg = config or PushConfig()
    pts = np.asarray(object_points, dtype=np.float64).reshape(-1, 3)
    if len(pts) == 0:
        raise PlanningError("cannot push an object with no observed points")
    centre = pts.mean(axis=0)
    goal = lookahead_point(np.asarray(path, dtype=np.float64), cfg.lookahead_m)
    n = cfg.n_samples
    pushes, side, ring = sample_pushes(pts, rng, cfg, axis)
    contacts, directions, distances = pushes

    # the object's outline at the centre's height, predicted with its centre
    prediction = (model or TranslationPush()).predict(
        centre, centre + ring, PushBatch(contacts, directions, distances))
    predicted = prediction.centres
    score = np.linalg.norm(predicted - goal, axis=1)
    if cost_map is not None:
        vox = cost_map.grid.world_to_voxel(predicted, clip=True)
        score += cfg.cost_weight * cost_map.cost[vox[:, 0], vox[:, 1], vox[:, 2]]
        score += cfg.collision_weight * _outline_hits(prediction.points, cost_map)
        # the centre where the planner's path may not go (the avoidance core): as bad as the
        # whole outline inside an obstacle
        blocked = cost_map.obstacles[vox[:, 0], vox[:, 1], vox[:, 2]]
        score += cfg.collision_weight * prediction.points.shape[1] * blocked
    if refused is not None and len(refused):
        near = directions @ np.asarray(refused, dtype=np.float64).reshape(-1, 3).T
        score = score + _REFUSED * (near.max(axis=1) >= np.cos(np.radians(cfg.refused_angle_deg)))
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


