"""Open-vocabulary perception: OWLv2 boxes, SAM masks, tracked masks, fused in 3-D.

Public API:

* :func:`open_vocab_perceiver` (weights from local directories → a perceiver) and
  :class:`OpenVocabPerceiver` (the :class:`~voxposer.perception.perceiver.Perceiver`)
* :class:`Detector`, :class:`OwlDetector`, :class:`Detection` (boxes for text queries)
* :class:`Segmenter`, :class:`SamSegmenter` (masks for boxes)
* :class:`MaskTracker`, :class:`TrackStep` (masks carried between frames)
* :class:`ViewMask`, :class:`Instance`, :func:`fuse_masks`, :func:`labelled_cloud` (3-D fusion)
* :func:`load_model` (weights from a directory, never downloaded)

Importing this package does not import torch or transformers; loading a model does (the
``vision`` extra).
"""

from voxposer.perception.open_vocab.boxes import Detection
from voxposer.perception.open_vocab.detector import Detector, OwlDetector
from voxposer.perception.open_vocab.factory import open_vocab_perceiver
from voxposer.perception.open_vocab.fusion import Instance, ViewMask, fuse_masks, labelled_cloud
from voxposer.perception.open_vocab.perceiver import DEFAULT_QUERIES, OpenVocabPerceiver
from voxposer.perception.open_vocab.segmenter import SamSegmenter, Segmenter
from voxposer.perception.open_vocab.tracker import MaskTracker, TrackStep
from voxposer.perception.open_vocab.weights import load_model

__all__ = [
    "DEFAULT_QUERIES",
    "Detection",
    "Detector",
    "Instance",
    "MaskTracker",
    "OpenVocabPerceiver",
    "OwlDetector",
    "SamSegmenter",
    "Segmenter",
    "TrackStep",
    "ViewMask",
    "fuse_masks",
    "labelled_cloud",
    "load_model",
    "open_vocab_perceiver",
]
