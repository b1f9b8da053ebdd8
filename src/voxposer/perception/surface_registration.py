"""Refining the cameras' extrinsics against each other from what they all see (multi-view ICP).

A rig's extrinsic calibration drifts by a few tenths of a degree and a few millimetres; fused,
four slightly misplaced views smear every object by ~1 cm on the sides one camera pair sees and
the other does not (a pushed block looks ~1 cm wider, so the pusher's contact sits early). The
views overlap, so their disagreement can be measured and removed, as multi-camera rigs do:

- **point-to-plane ICP** (Chen & Medioni) of each camera's cloud onto the other cameras' clouds
  fixes the directions the surfaces' normals constrain (the table: height and tilt; the
  objects' vertical faces: the horizontal directions across them);
- **raised horizontal patches** (the tops of blocks and furniture) are seen whole by every
  camera, so their centroids are correspondences in the horizontal directions that only
  one pair of cameras sees faces across (left cameras see the blocks' left faces, right
  cameras their right faces: nothing else pins the left pair's offset from the right pair's).
  Patches a camera sees clipped (dark surfaces losing depth, occlusion) are left out by area
  and by a median test of their offsets.

The cameras are moved together, Gauss–Seidel style (each onto the others, a few rounds), and the
rig's mean motion is removed at the end: the registration makes the views agree without
moving the rig as a whole (its mean calibration is the best estimate of where it is).
The world frame's z = 0 is the table top (raised patches are those above it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from voxposer.config_checks import require_below, require_int_at_least, require_positive


@dataclass(frozen=True)
class RegistrationConfig:
    """How the views are registered.

    Attributes:
        voxel_m: cell of the averaged clouds ICP matches [m], 0.006.
        rounds: Gauss–Seidel rounds (each camera moved once per round), 8.
        match_radius_m: farthest ICP correspondence in the first round [m], 0.03 (shrinks by
            0.7 per round down to 0.008).
        patch_cell_m: cell of the raised patches' connectivity [m], 0.005.
        patch_min_height_m: height above the table (world z) of a raised patch [m], 0.01.
        patch_max_height_m: ... and at most this [m], 0.12: the tops of things standing on
            the table (a block's is at 0.05), not the robot's links or a cabinet's top and
            drawers, which the cameras see cut off in different places.
        patch_min_cells: a raised top's least area in cells, 30 (~7.5 cm²).
        patch_max_cells: ... and most, 200 (50 cm²: a block's top, not a cabinet's or an open
            drawer's floor, which the cameras see cut off in different places).
        patch_match_m: farthest a patch's centroid may lie from its match in another view [m],
            0.025.
        patch_trim_m: a patch's offset further than this from the camera's median patch offset
            is left out [m], 0.005 (a patch the camera sees clipped).
        min_patches: the fewest raised tops every camera must share with the others (after
            the median test) for the registration to count, 2: with fewer, the horizontal
            offset between the left and the right cameras is left to the surfaces, which in
            a scene of large planes (a cabinet beside a single block) pull it astray — the
            views are kept as calibrated.
        max_rotation_deg: a correction rotating more than this is refused (the views kept as
            they came) [deg], 2.
        max_translation_m: ... or moving further than this [m], 0.03.
    """

    voxel_m: float = 0.006
    rounds: int = 8
    match_radius_m: float = 0.03
    patch_cell_m: float = 0.005
    patch_min_height_m: float = 0.01
    patch_max_height_m: float = 0.12
    patch_min_cells: int = 30
    patch_max_cells: int = 200
    patch_match_m: float = 0.025
    patch_trim_m: float = 0.005
    min_patches: int = 2
    max_rotation_deg: float = 2.0
    max_translation_m: float = 0.03

    def __post_init__(self) -> None:
        require_positive(self, "voxel_m", "match_radius_m", "patch_cell_m", "patch_max_height_m",
                         "patch_match_m", "patch_trim_m", "max_rotation_deg", "max_translation_m")
        require_int_at_least(self, 1, "rounds", "patch_min_cells", "patch_max_cells", "min_patches")
        require_below(self, "patch_min_height_m", "patch_max_height_m")
        require_below(self, "patch_min_cells", "patch_max_cells")


@dataclass(frozen=True)
class _View:
    """One camera's cloud prepared for matching (world frame, before any correction)."""

    points: NDArray[np.float64]   # (N, 3) voxel-averaged points [m]
    normals: NDArray[np.float64]  # (N, 3) unit PCA normals
    tree: cKDTree
    patches: NDArray[np.float64]  # (K, 3) raised patches' centroids [m]
    areas: NDArray[np.float64]    # (K,) their areas [cells]


def _downsample(points: NDArray[np.float64], cell: float, min_count: int) -> NDArray[np.float64]:
    """The mean point of every ``cell``-sized voxel holding ≥ ``min_count`` points, shape (M, 3)."""
    key = np.floor(points / cell).astype(np.int64)
    key -= key.min(axis=0)
    dims = key.max(axis=0) + 1
    flat = (key[:, 0] * dims[1] + key[:, 1]) * dims[2] + key[:, 2]
    _, inverse, counts = np.unique(flat, return_inverse=True, return_counts=True)
    sums = np.zeros((len(counts), 3))
    np.add.at(sums, inverse, points)
    keep = counts >= min_count
    return sums[keep] / counts[keep, None]


def _pca_normals(points: NDArray[np.float64], tree: cKDTree, k: int) -> NDArray[np.float64]:
    """Unit normals, shape (N, 3): the least-variance axis of each point's ``k`` neighbours."""
    _, idx = tree.query(points, k=min(k, len(points)))
    nbrs = points[idx] - points[idx].mean(axis=1, keepdims=True)
    _, vecs = np.linalg.eigh(np.einsum("nki,nkj->nij", nbrs, nbrs))
    return vecs[:, :, 0]


def _raised_patches(points: NDArray[np.float64], config: RegistrationConfig
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centroids (K, 3) [m] and areas (K,) [cells] of the connected, level, raised surfaces.

    Level: the cell's normal within ~25° of vertical. Biased by a millimetre or two towards or
    away from the camera (the sampling of a top's far, occluding edge and the tilted normals at
    its near edge differ per view): the floor of what the registration resolves.
    """
    cells = _downsample(points, config.patch_cell_m, 1)
    if len(cells) < config.patch_min_cells:
        return np.zeros((0, 3)), np.zeros(0)
    normals = _pca_normals(cells, cKDTree(cells), 12)
    top = cells[(np.abs(normals[:, 2]) > 0.9) & (cells[:, 2] > config.patch_min_height_m)
                & (cells[:, 2] < config.patch_max_height_m)]
    if len(top) == 0:
        return np.zeros((0, 3)), np.zeros(0)
    key = np.floor(top / [config.patch_cell_m, config.patch_cell_m, 0.01]).astype(np.int64)
    key -= key.min(axis=0)
    occupied = np.zeros(key.max(axis=0) + 1, dtype=bool)
    occupied[tuple(key.T)] = True
    labels, count = ndimage.label(occupied, structure=np.ones((3, 3, 3), dtype=bool))
    of_point = labels[tuple(key.T)]
    areas = np.bincount(of_point, minlength=count + 1).astype(np.float64)
    sums = np.stack([np.bincount(of_point, top[:, a], minlength=count + 1) for a in range(3)], 1)
    keep = (areas >= config.patch_min_cells) & (areas <= config.patch_max_cells)
    keep[0] = False
    return sums[keep] / areas[keep, None], areas[keep]


def _prepare(points: NDArray[np.float64], config: RegistrationConfig) -> _View:
    down = _downsample(points, config.voxel_m, 2)
    tree = cKDTree(down)
    patches, areas = _raised_patches(points, config)
    return _View(down, _pca_normals(down, tree, 16), tree, patches, areas)


def _transform(t: NDArray[np.float64], p: NDArray[np.float64]) -> NDArray[np.float64]:
    return p @ t[:3, :3].T + t[:3, 3]


def _twist(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """The 4x4 transform of a rotation vector x[:3] [rad] and translation x[3:] [m]."""
    out = np.eye(4)
    out[:3, :3] = Rotation.from_rotvec(x[:3]).as_matrix()
    out[:3, 3] = x[3:]
    return out


def _spread(indices: NDArray[np.intp], most: int) -> NDArray[np.intp]:
    """At most ``most`` of ``indices``, evenly spaced (deterministic subsampling)."""
    if len(indices) <= most:
        return indices
    return indices[np.linspace(0, len(indices) - 1, most).astype(np.intp)]


def _plane_rows(views: Sequence[_View], moves: Sequence[NDArray[np.float64]], cam: int,
                radius: float) -> tuple[NDArray[np.float64], NDArray[np.float64], int]:
    """Point-to-plane rows (A (M, 6), b (M,)) of camera ``cam``'s points onto their nearest
    neighbours among the other views (under their current ``moves``), and M."""
    view = views[cam]
    upright = np.abs(view.normals[:, 2])
    pick = np.concatenate([_spread(np.flatnonzero(upright < 0.6), 3000),
                           _spread(np.flatnonzero(upright >= 0.6), 1500)])
    src = _transform(moves[cam], view.points[pick])
    best = np.full(len(src), np.inf)
    near, normal = np.zeros_like(src), np.zeros_like(src)
    for other, seen in enumerate(views):
        if other == cam:
            continue
        back = np.linalg.inv(moves[other]).astype(np.float64)
        dist, idx = seen.tree.query(_transform(back, src), distance_upper_bound=radius)
        closer = np.isfinite(dist) & (dist < best)
        best[closer] = dist[closer]
        near[closer] = _transform(moves[other], seen.points[idx[closer]])
        normal[closer] = seen.normals[idx[closer]] @ moves[other][:3, :3].T
    ok = np.isfinite(best)
    p, q, n = src[ok], near[ok], normal[ok]
    return (np.concatenate([np.cross(p, n), n], axis=1),
            -np.einsum("ij,ij->i", p - q, n), int(ok.sum()))


def _patch_rows(views: Sequence[_View], moves: Sequence[NDArray[np.float64]], cam: int,
                weight: float, config: RegistrationConfig
                ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rows pulling camera ``cam``'s raised patches' centroids horizontally onto the mean of
    their matches in the other views, two per patch (x, y); the patches' squared weights sum
    to ``weight``."""
    view = views[cam]
    mine = _transform(moves[cam], view.patches)
    others = [(_transform(moves[o], v.patches), v.areas) for o, v in enumerate(views) if o != cam]
    found: list[tuple[NDArray[np.float64], NDArray[np.float64], float]] = []
    for centre, area in zip(mine, view.areas, strict=True):
        matches = []
        for theirs, their_areas in others:
            if len(theirs) == 0:
                continue
            gap = np.linalg.norm(theirs[:, :2] - centre[:2], axis=1)
            j = int(np.argmin(gap))
            if gap[j] < config.patch_match_m and \
                    abs(their_areas[j] - area) < 0.5 * max(their_areas[j], area):
                matches.append(theirs[j])
        if matches:
            found.append((centre, np.mean(matches, axis=0) - centre, float(area)))
    if len(found) >= 3:
        median = np.median([offset[:2] for _, offset, _ in found], axis=0)
        found = [f for f in found if np.linalg.norm(f[1][:2] - median) <= config.patch_trim_m]
    if not found:
        return np.zeros((0, 6)), np.zeros(0)
    total = sum(area for _, _, area in found)
    rows, rhs = [], []
    for (x, y, z), offset, area in found:
        w = np.sqrt(weight * area / total)
        # d(R p + t)/d(rotvec, t) for the x and y components at p = (x, y, z)
        rows.append(w * np.array([[0.0, z, -y, 1.0, 0.0, 0.0], [-z, 0.0, x, 0.0, 1.0, 0.0]]))
        rhs.append(w * offset[:2])
    return np.concatenate(rows), np.concatenate(rhs)


def register_clouds(clouds: Sequence[NDArray[np.float64]],
                    config: RegistrationConfig | None = None) -> list[NDArray[np.float64]]:
    """World-frame corrections that make ``clouds`` agree: one 4x4 transform per cloud, to be
    applied on the left of its camera's camera-to-world extrinsics (``C @ E``).

    Args:
        clouds: each camera's points in the world frame [m], shape (N_i, 3) (its whole view,
            cropped to the workspace; at least two cameras for anything to register).
        config: see :class:`RegistrationConfig`.

    Returns:
        the corrections; identity for every camera (left as calibrated) when fewer than two
        clouds were given, some camera shares fewer than ``config.min_patches`` raised tops
        with the others, or the registration moved some camera further than ``config``
        allows.
    """
    config = config or RegistrationConfig()
    identity = [np.eye(4) for _ in clouds]
    if len(clouds) < 2 or any(len(c) < 100 for c in clouds):
        return identity
    views = [_prepare(np.asarray(c, dtype=np.float64), config) for c in clouds]
    moves = [np.eye(4) for _ in clouds]
    for round_ in range(config.rounds):
        radius = max(config.match_radius_m * 0.7 ** round_, 0.008)
        for cam in range(len(views)):
            a, b, matched = _plane_rows(views, moves, cam, radius)
            pa, pb = _patch_rows(views, moves, cam, 0.5 * matched, config)
            if round_ == config.rounds - 1 and len(pb) < 2 * config.min_patches:
                return identity  # too few shared tops: see RegistrationConfig.min_patches
            if matched + len(pb) < 50:
                continue
            step, *_ = np.linalg.lstsq(np.concatenate([a, pa]), np.concatenate([b, pb]),
                                       rcond=None)
            moves[cam] = _twist(step) @ moves[cam]
    mean = np.concatenate([
        np.mean([Rotation.from_matrix(m[:3, :3]).as_rotvec() for m in moves], axis=0),
        np.mean([m[:3, 3] for m in moves], axis=0)])
    moves = [np.linalg.inv(_twist(mean)) @ m for m in moves]
    for m in moves:
        angle_deg, shift_m = correction_size(m)
        if angle_deg > config.max_rotation_deg or shift_m > config.max_translation_m:
            return identity
    return moves


def correction_size(move: NDArray[np.float64]) -> tuple[float, float]:
    """The size of a 4x4 correction: its rotation angle [deg] and its translation at the world
    origin [m]."""
    angle = np.linalg.norm(Rotation.from_matrix(move[:3, :3]).as_rotvec())
    return float(np.degrees(angle)), float(np.linalg.norm(move[:3, 3]))


__all__ = ["RegistrationConfig", "correction_size", "register_clouds"]
