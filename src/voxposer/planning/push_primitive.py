"""The pushing primitive: its parameters, a chosen push, and the end-effector waypoints.

A push is parametrised by a contact point on the object, a push direction in the table plane
and a push distance (paper Sec. 4 "Dynamics Model"). :func:`voxposer.planning.mpc.random_shooting`
chooses one through a :class:`~voxposer.planning.dynamics.DynamicsModel`; :func:`push_waypoints`
turns it into the hand's motion (approach from behind, push, retreat, lift).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, QhullError

from voxposer.errors import ConfigError
from voxposer.planning.trajectory import resample


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
        refused_angle_deg: a push within this angle [deg] of one the arm could not reach from
            about the same place is not chosen again while another is left (the MPC kept
            choosing the same unreachable push until the push budget ran out).
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
    refused_angle_deg: float = 30.0

    def __post_init__(self) -> None:
        if self.n_samples < 1:
            raise ConfigError(f"PushConfig.n_samples must be >= 1; got {self.n_samples!r}")
        if not 0 < self.min_distance_m <= self.max_distance_m:
            raise ConfigError(
                "PushConfig needs 0 < min_distance_m <= max_distance_m; got "
                f"{self.min_distance_m!r}, {self.max_distance_m!r}"
            )
        if not 0 <= self.refused_angle_deg <= 180:
            raise ConfigError(f"PushConfig.refused_angle_deg must be in [0, 180] [deg]; got "
                              f"{self.refused_angle_deg!r}")
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


def footprint(points: NDArray[np.float64], spacing: float = 0.01) -> NDArray[np.float64]:
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
