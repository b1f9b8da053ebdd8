"""A built-in synthetic scene for planning without a simulator or a language model.

A 1 m cube workspace over a table holds a cup-shaped obstacle (a box open towards the start)
with the affordance target just behind its closed end, a few random obstacle blobs, and one
object to stay away from. The paper's released greedy planner walks into the cup and stalls;
the global planner goes around it. Used by ``voxposer plan-demo``, the planner benchmark and tests.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.valuemaps.maps import ValueMapAPI


@dataclass(frozen=True)
class SyntheticScene:
    """Everything the planner needs, as perception and the LLM would provide it.

    Attributes:
        grid: the workspace grid.
        points: scene surface points [m], shape (N, 3) (what a depth camera would see).
        start: the end effector's position [m], shape (3,).
        target: the point the affordance map marks [m], shape (3,).
        avoid_centre: centre of the object to stay away from [m], shape (3,).
        affordance_map: shape ``grid.shape``; 1 at the target.
        avoidance_map: shape ``grid.shape``; 1 within 10 cm of ``avoid_centre``.
        velocity_map: shape ``grid.shape``; 0.5 within 10 cm of the target, 1 elsewhere.
        gripper_map: shape ``grid.shape``; 1 (closed) within 3 cm of the target, 0 elsewhere.
        rotation_map: shape ``(*grid.shape, 4)``; pointing +x within 10 cm of the target.
        occupancy: obstacle voxels from ``points``, shape ``grid.shape``.
    """

    grid: VoxelGrid
    points: NDArray[np.float64]
    start: NDArray[np.float64]
    target: NDArray[np.float64]
    avoid_centre: NDArray[np.float64]
    affordance_map: NDArray[np.float32]
    avoidance_map: NDArray[np.float32]
    velocity_map: NDArray[np.float32]
    gripper_map: NDArray[np.float32]
    rotation_map: NDArray[np.float32]
    occupancy: NDArray[np.bool_]


def box_surface_points(lo: NDArray, hi: NDArray, spacing: float = 0.005) -> NDArray[np.float64]:
    """Points on the six faces of the axis-aligned box [lo, hi] [m], about ``spacing`` apart."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    faces = []
    for axis in range(3):
        others = [a for a in range(3) if a != axis]
        u = np.linspace(
            lo[others[0]], hi[others[0]], max(int((hi - lo)[others[0]] / spacing), 1) + 1
        )
        v = np.linspace(
            lo[others[1]], hi[others[1]], max(int((hi - lo)[others[1]] / spacing), 1) + 1
        )
        uu, vv = np.meshgrid(u, v, indexing="ij")
        for value in (lo[axis], hi[axis]):
            face = np.empty((uu.size, 3))
            face[:, axis] = value
            face[:, others[0]] = uu.ravel()
            face[:, others[1]] = vv.ravel()
            faces.append(face)
    return np.concatenate(faces)


def sphere_surface_points(
    centre: NDArray, radius: float, spacing: float = 0.005
) -> NDArray[np.float64]:
    """Points on a sphere [m] (a Fibonacci lattice about ``spacing`` apart)."""
    n = max(int(4 * np.pi * radius**2 / spacing**2), 16)
    i = np.arange(n) + 0.5
    phi = np.arccos(1 - 2 * i / n)
    theta = np.pi * (1 + 5**0.5) * i
    unit = np.stack([np.cos(theta) * np.sin(phi), np.sin(theta) * np.sin(phi), np.cos(phi)], axis=1)
    return np.asarray(centre, float) + radius * unit


def make_synthetic_scene(
    rng: np.random.Generator, shape: tuple[int, int, int] = (100, 100, 100), n_blobs: int = 4
) -> SyntheticScene:
    """Build the synthetic scene; ``rng`` places the obstacle blobs (the cup is fixed)."""
    grid = VoxelGrid((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), shape)
    start = np.array([0.15, 0.5, 0.35])
    target = np.array([0.80, 0.5, 0.35])
    walls = [  # a cup open towards -x (the start); target 10 cm behind its closed end
        ((0.64, 0.30, 0.15), (0.68, 0.70, 0.55)),  # closed end
        ((0.42, 0.30, 0.15), (0.68, 0.33, 0.55)),  # side (-y)
        ((0.42, 0.67, 0.15), (0.68, 0.70, 0.55)),  # side (+y)
        ((0.42, 0.30, 0.15), (0.68, 0.70, 0.18)),  # floor
        ((0.42, 0.30, 0.52), (0.68, 0.70, 0.55)),  # ceiling
    ]
    parts = [box_surface_points(np.array(lo), np.array(hi)) for lo, hi in walls]
    parts.append(box_surface_points(np.array([0.0, 0.0, 0.0]), np.array([1.0, 1.0, 0.02]), 0.008))
    placed = 0
    while placed < n_blobs:  # blobs away from the start, the target and the cup
        centre = rng.uniform([0.1, 0.1, 0.1], [0.9, 0.9, 0.8])
        radius = float(rng.uniform(0.04, 0.08))
        clear = min(np.linalg.norm(centre - start), np.linalg.norm(centre - target))
        in_cup = np.all(centre > np.array([0.34, 0.22, 0.07])) and np.all(
            centre < np.array([0.76, 0.78, 0.63])
        )
        if clear > radius + 0.1 and not in_cup:
            parts.append(sphere_surface_points(centre, radius))
            placed += 1
    avoid_centre = np.array([0.30, 0.22, 0.35])
    return scene_from_points(grid, np.concatenate(parts), start, target, avoid_centre)


def scene_from_points(grid: VoxelGrid, obstacles: NDArray[np.float64], start: NDArray[np.float64],
                      target: NDArray[np.float64], avoid_centre: NDArray[np.float64]
                      ) -> SyntheticScene:
    """The scene of obstacle surface points ``obstacles`` [m], shape (N, 3), with a 5 cm box to
    stay away from at ``avoid_centre`` [m] (added to the points) and the value maps of
    :class:`SyntheticScene` around ``target`` [m]; ``start`` [m] is the end effector."""
    points = np.concatenate([obstacles,
                             box_surface_points(avoid_centre - 0.025, avoid_centre + 0.025)])
    api = ValueMapAPI(grid)
    target_vox = grid.world_to_voxel(target)
    affordance = api.get_empty_affordance_map()
    affordance[tuple(target_vox)] = 1.0
    avoidance = api.get_empty_avoidance_map()
    api.set_voxel_by_radius(avoidance, grid.world_to_voxel(avoid_centre), 10, 1.0)
    velocity = api.get_empty_velocity_map()
    api.set_voxel_by_radius(velocity, target_vox, 10, 0.5)
    gripper = api.get_empty_gripper_map()
    api.set_voxel_by_radius(gripper, target_vox, 3, 1.0)
    rotation = api.get_empty_rotation_map()
    api.set_voxel_by_radius(rotation, target_vox, 10, api.pointat2quat([1.0, 0.0, 0.0]))
    return SyntheticScene(
        grid=grid,
        points=points,
        start=np.asarray(start, dtype=np.float64),
        target=grid.voxel_to_world(target_vox),
        avoid_centre=avoid_centre,
        affordance_map=affordance,
        avoidance_map=avoidance,
        velocity_map=velocity,
        gripper_map=gripper,
        rotation_map=rotation,
        occupancy=grid.points_to_occupancy(points),
    )
