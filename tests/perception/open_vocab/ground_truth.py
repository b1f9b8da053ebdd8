"""A detector and a segmenter faked from the simulator's segmentation channel (for tests).

They stand in for OWLv2 and SAM with perfect answers, so tests of fusion, tracking and naming
check geometry and identity rather than a network's accuracy. Both find the camera an image came
from by identity (``rgb is frame.rgb``) in the source's current observation.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.perception.observation import CameraFrame
from voxposer.perception.open_vocab.boxes import Detection, mask_box
from voxposer.perception.recorded import RecordedObservations


class GroundTruthModels:
    """Detector (``detect``) and segmenter (``segment``) from ground-truth object ids.

    Args:
        source: the observation source the perceiver reads (its ``observation`` may change).
        objects: query → the label names it finds (e.g. "block" → the blue and green blocks).
    """

    def __init__(self, source: RecordedObservations, objects: dict[str, tuple[str, ...]]
                 ) -> None:
        self.source = source
        self.objects = objects
        self.detect_calls = 0

    def _frame(self, rgb: NDArray[np.uint8]) -> CameraFrame:
        for frame in self.source.observation.cameras:
            if frame.rgb is rgb:
                return frame
        raise LookupError("image of no camera of the current observation")

    def _label(self, name: str) -> int:
        return self.source.observation.label_names.index(name)

    def detect(self, rgb: NDArray[np.uint8], queries: Sequence[str]) -> list[Detection]:
        self.detect_calls += 1
        ids = self._frame(rgb).object_ids
        found = []
        for q, query in enumerate(queries):
            for name in self.objects.get(query, ()):
                mask = ids == self._label(name)
                if mask.sum() >= 10:
                    found.append(Detection(mask_box(mask), 0.9 - 0.1 * len(found), q))
        return found

    def segment(self, rgb: NDArray[np.uint8], boxes: ArrayLike) -> NDArray[np.bool_]:
        """The whole segment of the known object with most pixels in each box (SAM-like)."""
        ids = self._frame(rgb).object_ids
        labels = [self._label(n) for names in self.objects.values() for n in names]
        out = np.zeros((0, *ids.shape), dtype=bool)
        for box in np.asarray(boxes, dtype=np.float64).reshape(-1, 4):
            x0, y0, x1, y1 = np.round(box).astype(int)
            inside = ids[y0:y1, x0:x1]
            counts = [int(np.count_nonzero(inside == k)) for k in labels]
            best = labels[int(np.argmax(counts))] if max(counts, default=0) else None
            mask = ids == best if best is not None else np.zeros(ids.shape, dtype=bool)
            out = np.concatenate([out, mask[None]])
        return out
