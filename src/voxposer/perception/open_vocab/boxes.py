"""Image boxes: what the detector reports, and the box arithmetic detection and tracking share.

Boxes are pixel ``xyxy``: (x_min, y_min, x_max, y_max) [px], x along columns (right), y along
rows (down), as in :class:`voxposer.perception.observation.CameraFrame`; a pixel (u, v) is inside
when ``x_min <= u < x_max`` and ``y_min <= v < y_max``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray


class Detection(NamedTuple):
    """One box the open-vocabulary detector found.

    Attributes:
        box: pixel xyxy [px], shape (4,), float64.
        score: the detector's confidence in [0, 1].
        query: index of the text query it answers (into the detector's ``queries``).
    """

    box: NDArray[np.float64]
    score: float
    query: int


def box_iou(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """Intersection over union of boxes ``a`` (shape (N, 4)) and ``b`` (shape (M, 4)), shape
    (N, M); 0 where both are empty."""
    a = np.asarray(a, dtype=np.float64).reshape(-1, 4)
    b = np.asarray(b, dtype=np.float64).reshape(-1, 4)
    lo = np.maximum(a[:, None, :2], b[None, :, :2])
    hi = np.minimum(a[:, None, 2:], b[None, :, 2:])
    inter = np.prod(np.clip(hi - lo, 0.0, None), axis=-1)
    area_a = np.prod(np.clip(a[:, 2:] - a[:, :2], 0.0, None), axis=-1)
    area_b = np.prod(np.clip(b[:, 2:] - b[:, :2], 0.0, None), axis=-1)
    union = area_a[:, None] + area_b[None, :] - inter
    return np.where(union > 0, inter / np.where(union > 0, union, 1.0), 0.0)


def mask_box(mask: NDArray[np.bool_]) -> NDArray[np.float64]:
    """The tight pixel xyxy box, shape (4,), of a boolean mask, shape (H, W); all zeros when the
    mask is empty."""
    rows = np.flatnonzero(mask.any(axis=1))
    cols = np.flatnonzero(mask.any(axis=0))
    if len(rows) == 0:
        return np.zeros(4)
    return np.array([cols[0], rows[0], cols[-1] + 1, rows[-1] + 1], dtype=np.float64)


def expand_box(box: ArrayLike, margin: float, width: int, height: int) -> NDArray[np.float64]:
    """``box`` (xyxy, shape (4,)) grown by ``margin`` times its size on every side, clipped to
    a ``width`` x ``height`` [px] image."""
    b = np.asarray(box, dtype=np.float64)
    size = b[2:] - b[:2]
    grown = np.concatenate([b[:2] - margin * size, b[2:] + margin * size])
    return np.clip(grown, 0.0, [width, height, width, height])


def non_max_suppression(boxes: NDArray[np.float64], scores: NDArray[np.float64],
                        iou: float) -> NDArray[np.int64]:
    """Indices of the boxes (shape (N, 4)) kept by greedy non-maximum suppression: best score
    first, dropping any box overlapping a kept one by more than ``iou``."""
    order = np.argsort(-scores, kind="stable")
    keep: list[int] = []
    for k in order:
        if not keep or np.all(box_iou(boxes[k], boxes[keep])[0] <= iou):
            keep.append(int(k))
    return np.asarray(keep, dtype=np.int64)
