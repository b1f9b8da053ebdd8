"""Frames and orientations every stage shares: quaternion conventions and the top-down grasp.

Public quaternions are scalar-last (x, y, z, w), as in :mod:`scipy.spatial.transform`; MuJoCo's
are scalar-first (w, x, y, z) and are converted at the simulator's boundary. The end effector's
approach axis is its local +z.
"""

from __future__ import annotations

from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from voxposer.geometry.voxel_grid import unit_direction

#: Orientation of the end effector pointing straight down, scalar-last (x, y, z, w): its local
#: +z (approach axis) along world −z, local +x along world +y and local +y along world +x (the
#: Panda hand's fingers close along its local x: along world y). A half turn about
#: (1, 1, 0)/√2.
TOP_DOWN_QUAT: Final = (float(np.sqrt(0.5)), float(np.sqrt(0.5)), 0.0, 0.0)


def wxyz_to_xyzw(q: ArrayLike) -> NDArray[np.float64]:
    """Scalar-first (MuJoCo) → scalar-last (scipy) quaternion, shape (4,)."""
    a = np.asarray(q, dtype=np.float64)
    return np.array([a[1], a[2], a[3], a[0]])


def xyzw_to_wxyz(q: ArrayLike) -> NDArray[np.float64]:
    """Scalar-last (scipy) → scalar-first (MuJoCo) quaternion, shape (4,)."""
    a = np.asarray(q, dtype=np.float64)
    return np.array([a[3], a[0], a[1], a[2]])


def pointat2quat(vector: ArrayLike, fingers: ArrayLike | None = None) -> NDArray[np.float64]:
    """Quaternion (x, y, z, w) that points the end effector's approach axis along ``vector``.

    The rotation is the smallest one that turns the top-down grasp orientation
    (:data:`TOP_DOWN_QUAT`, approach along world −z) so that its approach axis is ``vector``.
    ``vector`` is a world direction, shape (3,); it need not be normalised. With ``fingers``
    (a world direction, shape (3,)) the hand is then turned about its approach so that the
    fingers close along ``fingers`` as nearly as the approach allows (across a bar, say; a
    direction along the approach itself is ignored).
    """
    target = unit_direction(vector)
    down = np.array([0.0, 0.0, -1.0])
    if np.allclose(target, -down):
        align = Rotation.from_rotvec(np.pi * np.array([0.0, 1.0, 0.0]))
    else:
        align, _ = Rotation.align_vectors(target[None], down[None])
    rot = align * Rotation.from_quat(TOP_DOWN_QUAT)
    if fingers is not None:
        f = np.asarray(fingers, dtype=np.float64).reshape(3)
        f = f - (f @ target) * target
        if np.linalg.norm(f) > 1e-9:
            now = rot.apply([1.0, 0.0, 0.0])  # the fingers close along the hand's local x
            angle = np.arctan2(np.cross(now, f) @ target, now @ f)
            if abs(angle) > np.pi / 2:  # the two fingers are alike: the smaller turn
                angle -= np.sign(angle) * np.pi
            rot = Rotation.from_rotvec(target * angle) * rot
    q = rot.as_quat()
    return q if q[3] >= 0 else -q
