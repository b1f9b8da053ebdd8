"""Surface normals of an organised point map (one camera's back-projected depth image).

At every pixel the horizontal and the vertical tangent are taken toward the neighbour with the
smaller depth jump (so edges keep good normals), crossed, and turned to face the camera; where
both neighbours along a direction jump by ``EDGE_JUMP`` or more, or the depth is missing, the
normal is left at zero. One compiled pass over the pixels (numba, cached on disk): the same
arithmetic as the array version it replaced, which built some forty full-image temporaries and
took ~11 ms per 320×240 view on 2 cores, about 40% of observing the four cameras.
"""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

#: A tangent whose depth jump exceeds this [m] crosses an edge; the normal there is left at 0.
EDGE_JUMP = 0.02
#: depth standing in for a missing one while tangents are taken [m] (so its jumps are edges)
_FAR = 1e6


@numba.njit(cache=True, nogil=True, inline="always")
def _tangent(x: np.ndarray, y: np.ndarray, z: np.ndarray, i: int, j: int, di: int, dj: int,
             n: int, at: int) -> tuple[float, float, float, bool]:  # pragma: no cover
    """Tangent at pixel (i, j) along (di, dj) toward the neighbour with the smaller depth jump;
    ``at`` is the pixel's index along that axis, ``n`` the axis length; and whether it is valid."""
    z0 = z[i, j] if np.isfinite(z[i, j]) else _FAR
    fwd = bwd = np.inf
    if at + 1 < n:
        z1 = z[i + di, j + dj] if np.isfinite(z[i + di, j + dj]) else _FAR
        fwd = abs(z1 - z0)
    if at > 0:
        zm = z[i - di, j - dj] if np.isfinite(z[i - di, j - dj]) else _FAR
        bwd = abs(z0 - zm)
    if bwd < fwd:  # backward difference: this pixel minus the previous one
        a, b = (i - di, j - dj), (i, j)
    elif at + 1 < n:
        a, b = (i, j), (i + di, j + dj)
    else:
        return 0.0, 0.0, 0.0, False
    xa = x[a] if np.isfinite(z[a]) else 0.0
    ya = y[a] if np.isfinite(z[a]) else 0.0
    za = z[a] if np.isfinite(z[a]) else _FAR
    xb = x[b] if np.isfinite(z[b]) else 0.0
    yb = y[b] if np.isfinite(z[b]) else 0.0
    zb = z[b] if np.isfinite(z[b]) else _FAR
    return xb - xa, yb - ya, zb - za, min(fwd, bwd) < EDGE_JUMP


@numba.njit(cache=True, nogil=True)
def normals_from_points(x: np.ndarray, y: np.ndarray, z: np.ndarray
                        ) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """Camera-frame unit normals, shape (H, W, 3) float32, facing the camera, and where they are
    valid, shape (H, W), from the camera-frame coordinates [m] of each pixel, each (H, W)
    float32 (NaN where the depth is missing)."""
    h, w = z.shape
    out = np.zeros((h, w, 3), dtype=np.float32)
    ok = np.zeros((h, w), dtype=np.bool_)
    for i in range(h):
        for j in range(w):
            if not np.isfinite(z[i, j]):
                continue
            ux, uy, uz, ok_u = _tangent(x, y, z, i, j, 0, 1, w, j)
            vx, vy, vz, ok_v = _tangent(x, y, z, i, j, 1, 0, h, i)
            nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
            norm = np.sqrt(nx * nx + ny * ny + nz * nz)
            if not (ok_u and ok_v and norm > 1e-12):
                continue
            scale = 1.0 / norm
            if nx * x[i, j] + ny * y[i, j] + nz * z[i, j] > 0:  # face the camera at the origin
                scale = -scale
            out[i, j, 0], out[i, j, 1], out[i, j, 2] = nx * scale, ny * scale, nz * scale
            ok[i, j] = True
    return out, ok


def camera_frame_normals(x: NDArray[np.float32], y: NDArray[np.float32], z: NDArray[np.float32]
                         ) -> tuple[NDArray[np.float32], NDArray[np.bool_]]:
    """:func:`normals_from_points` on contiguous float32 copies of ``x``, ``y``, ``z``."""
    def c(a: NDArray[np.float32]) -> NDArray[np.float32]:
        return np.ascontiguousarray(a, dtype=np.float32)

    return normals_from_points(c(x), c(y), c(z))
