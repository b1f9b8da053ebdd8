"""Mask tracking between detections: each object's masks carried to the next frame.

The paper tracks SAM's masks with XMem. :class:`MaskTracker` re-prompts the segmenter instead:
each view's previous box, moved by its last motion and grown by a margin, prompts the new frame.
A view is lost when its new mask is (nearly) empty, spills far outside its prompt (box IoU below
``min_iou``), or its 3-D centroid jumped more than ``max_step_m``; when two views of one camera
land on one object, the one that moved further is lost. Identity is kept in 3-D: a view stays
with its instance. Any loss is reported, so the caller can run the detector again.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.observation import CameraFrame
from voxposer.perception.open_vocab.boxes import box_iou, expand_box, mask_box
from voxposer.perception.open_vocab.fusion import (
    Instance,
    ViewMask,
    in_workspace,
    mask_points,
    world_points,
)
from voxposer.perception.open_vocab.segmenter import Segmenter

#: Two tracked masks of one camera overlapping by more than this IoU found the same object.
_SAME_OBJECT_IOU = 0.5


@dataclass(frozen=True)
class TrackStep:
    """The result of one tracking step.

    Attributes:
        instances: the instances with every view still tracked (new masks, centroids [m]);
            an instance no view tracks any more is left out.
        lost: names of the instances that lost at least one view.
    """

    instances: tuple[Instance, ...]
    lost: tuple[str, ...]


class MaskTracker:
    """Carries instances' masks from frame to frame by box-prompting a :class:`Segmenter`.

    Args:
        segmenter: the box-prompted segmenter.
        margin: the prompt box is the previous box grown by this fraction of its size per side.
        min_iou: a new mask whose box overlaps its prompt by less than this IoU is lost.
        min_pixels: a new mask with fewer pixels is lost.
        max_step_m: a view whose 3-D centroid moved further than this [m] is lost.
    """

    def __init__(self, segmenter: Segmenter, *, margin: float = 0.5, min_iou: float = 0.05,
                 min_pixels: int = 10, max_step_m: float = 0.1) -> None:
        for field, value in (("margin", margin), ("max_step_m", max_step_m)):
            if not value > 0:
                raise ConfigError(f"MaskTracker.{field} must be > 0; got {value!r}")
        if not 0.0 <= min_iou <= 1.0:
            raise ConfigError(f"MaskTracker.min_iou must be in [0, 1]; got {min_iou!r}")
        if min_pixels < 1:
            raise ConfigError(f"MaskTracker.min_pixels must be >= 1; got {min_pixels!r}")
        self.segmenter = segmenter
        self.margin = float(margin)
        self.min_iou = float(min_iou)
        self.min_pixels = int(min_pixels)
        self.max_step_m = float(max_step_m)

    def _camera_step(self, frame: CameraFrame, points: NDArray[np.float64],
                     views: list[tuple[int, ViewMask]], centroids: Sequence[NDArray[np.float64]],
                     grid: VoxelGrid) -> list[tuple[int, ViewMask, NDArray[np.float64]]]:
        """The views of one camera, (instance index, view), tracked into ``frame``: (instance
        index, new view, its points [m], shape (N, 3)) for each view kept."""
        h, w = frame.depth.shape
        old = [mask_box(v.mask) for _, v in views]
        prompts = np.array([expand_box(np.concatenate([b[:2] + v.motion, b[2:] + v.motion]),
                                       self.margin, w, h)
                            for b, (_, v) in zip(old, views, strict=True)])
        masks = self.segmenter.segment(frame.rgb, prompts)
        inside = in_workspace(points, grid)
        kept: dict[int, tuple[int, ViewMask, NDArray[np.float64], float]] = {}
        for j, ((inst, view), box, prompt, mask) in enumerate(
                zip(views, old, prompts, masks, strict=True)):
            new_box = mask_box(mask)
            pts = mask_points(points, mask, grid, inside)
            if (mask.sum() < self.min_pixels or len(pts) == 0
                    or box_iou(new_box, prompt)[0, 0] < self.min_iou):
                continue
            step = float(np.linalg.norm(pts.mean(axis=0) - centroids[inst]))
            if step > self.max_step_m:
                continue
            motion = (new_box[:2] + new_box[2:] - box[:2] - box[2:]) / 2.0
            tracked = ViewMask(view.camera, view.query, mask, view.score, motion)
            for other, (_, seen, _, other_step) in list(kept.items()):
                if _mask_iou(seen.mask, mask) > _SAME_OBJECT_IOU:
                    if other_step <= step:
                        break
                    del kept[other]
            else:
                kept[j] = (inst, tracked, pts, step)
        return [(inst, v, p) for inst, v, p, _ in kept.values()]

    def step(self, frames: Sequence[CameraFrame], instances: Sequence[Instance],
             grid: VoxelGrid, points: Sequence[NDArray[np.float64]] | None = None) -> TrackStep:
        """Track ``instances`` (from the previous frame) into ``frames``.

        Args:
            frames: the new views, in the cameras' order of the previous frame.
            instances: the instances of the previous frame.
            grid: the workspace grid (points outside it are ignored).
            points: :func:`~voxposer.perception.open_vocab.fusion.world_points` of ``frames``
                when already computed.
        """
        pts = list(points) if points is not None else world_points(frames)
        tracked: dict[int, list[tuple[ViewMask, NDArray[np.float64]]]] = {}
        centroids = [inst.centroid for inst in instances]
        for cam, frame in enumerate(frames):
            views = [(k, v) for k, inst in enumerate(instances) for v in inst.views
                     if v.camera == cam]
            if views:
                for k, view, view_pts in self._camera_step(frame, pts[cam], views, centroids,
                                                           grid):
                    tracked.setdefault(k, []).append((view, view_pts))
        out, lost = [], []
        for k, inst in enumerate(instances):
            views_now = tracked.get(k, [])
            if len(views_now) < len(inst.views):
                lost.append(inst.name)
            if views_now:
                centroid = np.concatenate([p for _, p in views_now]).mean(axis=0)
                out.append(Instance(inst.name, inst.query, tuple(v for v, _ in views_now),
                                    centroid))
        return TrackStep(tuple(out), tuple(lost))


def _mask_iou(a: NDArray[np.bool_], b: NDArray[np.bool_]) -> float:
    """Pixel intersection over union of two masks of one shape (0 when both are empty)."""
    union = int(np.count_nonzero(a | b))
    return int(np.count_nonzero(a & b)) / union if union else 0.0
