"""Box arithmetic shared by detection and tracking."""

from __future__ import annotations

import numpy as np

from voxposer.perception.open_vocab.boxes import (
    box_iou,
    expand_box,
    mask_box,
    non_max_suppression,
)


def test_iou_of_known_boxes() -> None:
    iou = box_iou([[0, 0, 10, 10]], [[0, 0, 10, 10], [5, 0, 15, 10], [20, 20, 30, 30],
                                     [3, 3, 3, 3]])
    np.testing.assert_allclose(iou, [[1.0, 50 / 150, 0.0, 0.0]])


def test_mask_box_is_tight_and_exclusive() -> None:
    mask = np.zeros((8, 10), dtype=bool)
    mask[2:5, 3:7] = True
    np.testing.assert_array_equal(mask_box(mask), [3, 2, 7, 5])
    np.testing.assert_array_equal(mask_box(np.zeros((4, 4), dtype=bool)), np.zeros(4))


def test_expand_box_grows_each_side_and_clips() -> None:
    np.testing.assert_allclose(expand_box([10, 10, 20, 30], 0.5, 100, 100), [5, 0, 25, 40])
    np.testing.assert_allclose(expand_box([90, 0, 100, 10], 1.0, 100, 50), [80, 0, 100, 20])


def test_nms_keeps_the_best_of_overlapping_boxes() -> None:
    boxes = np.array([[0, 0, 10, 10], [1, 1, 11, 11], [50, 50, 60, 60]], dtype=np.float64)
    kept = non_max_suppression(boxes, np.array([0.5, 0.9, 0.1]), iou=0.3)
    np.testing.assert_array_equal(kept, [1, 2])
