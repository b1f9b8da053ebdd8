"""Planner scenes of other kinds than the built-in cup: a wall with a gap, a target in a box
open on one side, and a target sealed in a box (no path exists).

They vary what makes planning hard — a detour through one narrow gap, a way in from one side
only, a search that must prove there is no way — and are drawn from a generator, so the planner
benchmark can report each kind on scenes it was not tuned on.
"""

from __future__ import annotations

from typing import Final, Literal

import numpy as np

from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.planning.synthetic_scene import (
    SyntheticScene,
    box_surface_points,
    make_synthetic_scene,
    scene_from_points,
)

SceneKind = Literal["cup", "wall", "enclosed", "sealed"]
SCENE_KINDS: Final[tuple[SceneKind, ...]] = ("cup", "wall", "enclosed", "sealed")
#: Half the side of the box around the target in "enclosed" and "sealed" scenes [m].
BOX_HALF_M: Final = 0.10


def make_scene(kind: str, rng: np.random.Generator,
               shape: tuple[int, int, int] = (100, 100, 100)) -> SyntheticScene:
    """A scene of ``kind`` on a 1 m cube of ``shape`` voxels; ``rng`` places its parts.

    - "cup": :func:`~voxposer.planning.synthetic_scene.make_synthetic_scene`.
    - "wall": a 3 cm wall across x between start and target, floor to ceiling, with one
      12 cm square gap at a random height and side position.
    - "enclosed": the target in a 20 cm box with one random face missing (not the floor).
    - "sealed": the same box closed on all six faces: the target is unreachable.

    Raises:
        ConfigError: an unknown ``kind`` (names the kinds).
    """
    if kind not in SCENE_KINDS:
        raise ConfigError(f"unknown planner scene kind {kind!r}; kinds are: "
                          f"{', '.join(SCENE_KINDS)}")
    if kind == "cup":
        return make_synthetic_scene(rng, shape)
    grid = VoxelGrid((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), shape)
    start = np.array([0.15, rng.uniform(0.3, 0.7), rng.uniform(0.25, 0.6)])
    target = np.array([0.78, rng.uniform(0.3, 0.7), rng.uniform(0.25, 0.6)])
    table = box_surface_points(np.zeros(3), np.array([1.0, 1.0, 0.02]), 0.008)
    if kind == "wall":
        parts = _wall_with_gap(rng)
    else:
        parts = _box_faces(target, open_face=None if kind == "sealed" else int(rng.integers(5)))
    avoid = np.array([0.35, rng.uniform(0.2, 0.8), rng.uniform(0.2, 0.6)])
    return scene_from_points(grid, np.concatenate([table, *parts]), start, target, avoid)


def _wall_with_gap(rng: np.random.Generator) -> list[np.ndarray]:
    """Surface points of a wall at x = 0.55–0.58 m over the whole cube but a 12 cm gap."""
    gap_y, gap_z = rng.uniform(0.1, 0.78), rng.uniform(0.1, 0.78)
    x0, x1, g = 0.55, 0.58, 0.12
    pieces = [((0.0, gap_y + g), (1.0, 1.0)), ((0.0, 0.0), (1.0, gap_y)),  # beside the gap
              ((gap_y, 0.0), (gap_y + g, gap_z)), ((gap_y, gap_z + g), (gap_y + g, 1.0))]
    out = []
    for (y0, z0), (y1, z1) in pieces:
        if y1 > y0 and z1 > z0:
            out.append(box_surface_points(np.array([x0, y0, z0]), np.array([x1, y1, z1])))
    return out


def _box_faces(centre: np.ndarray, open_face: int | None) -> list[np.ndarray]:
    """The six 2 cm thick walls of a cube of half side ``BOX_HALF_M`` around ``centre`` [m],
    without face ``open_face`` (0–4: −x, +x, −y, +y, +z; None: all six)."""
    h, t = BOX_HALF_M, 0.02
    faces = []
    for index, (axis, sign) in enumerate([(0, -1), (0, 1), (1, -1), (1, 1), (2, 1), (2, -1)]):
        if index == open_face:
            continue
        lo, hi = centre - h, centre + h
        if sign < 0:
            hi = hi.copy()
            hi[axis] = lo[axis] + t
        else:
            lo = lo.copy()
            lo[axis] = hi[axis] - t
        faces.append(box_surface_points(lo, hi))
    return faces
