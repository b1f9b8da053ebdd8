"""Building the open-vocabulary perceiver from model weights on disk (what the pipeline calls)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.perception.open_vocab.detector import OwlDetector
from voxposer.perception.open_vocab.perceiver import DEFAULT_QUERIES, OpenVocabPerceiver
from voxposer.perception.open_vocab.segmenter import SamSegmenter
from voxposer.perception.perceiver import ObservationSource


def open_vocab_perceiver(source: ObservationSource, grid: VoxelGrid,
                         detector_path: str | Path, segmenter_path: str | Path, *,
                         queries: Sequence[str] = DEFAULT_QUERIES,
                         threshold: float = 0.1) -> OpenVocabPerceiver:
    """An :class:`OpenVocabPerceiver` with OWLv2 and SAM loaded from local weights.

    Args:
        source: what observes the scene (the simulator, a camera driver).
        grid: the workspace grid.
        detector_path: directory (or locally cached model id) of an
            ``Owlv2ForObjectDetection`` and its tokenizer.
        segmenter_path: directory (or locally cached model id) of a ``SamModel``.
        queries: the names to look for (default: the tabletop catalog's names).
        threshold: the detector's minimum box score in [0, 1].

    Raises:
        ConfigError: a path holds no such model (names it and the expected class), or the
            ``vision`` extra (torch, transformers) is not installed.
    """
    detector = OwlDetector.from_pretrained(detector_path, threshold=threshold)
    segmenter = SamSegmenter.from_pretrained(segmenter_path)
    return OpenVocabPerceiver(source, grid, detector, segmenter, queries=queries)
