"""Open-vocabulary detection: boxes for free-form text queries in one RGB image (OWLv2).

The paper (App. A.5, real world) asks OWL-ViT for a box per object or part name. :class:`Detector`
is the seam; :class:`OwlDetector` wraps ``transformers``' ``Owlv2ForObjectDetection`` with its
own preprocessing (the processor's "fast" path needs torchvision): the image is padded to a
square at its bottom and right with grey, resized to the model's input size and normalised.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, Final, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.perception.open_vocab.boxes import Detection, non_max_suppression
from voxposer.perception.open_vocab.weights import (
    image_stats,
    load_model,
    load_tokenizer,
    require,
)

#: CLIP's per-channel normalisation of images in [0, 1] (OWLv2's default).
CLIP_MEAN: Final = (0.48145466, 0.4578275, 0.40821073)
CLIP_STD: Final = (0.26862954, 0.26130258, 0.27577711)


@runtime_checkable
class Detector(Protocol):
    """Finds boxes for text queries in an image."""

    def detect(self, rgb: NDArray[np.uint8], queries: Sequence[str]) -> list[Detection]:
        """Boxes in ``rgb`` (shape (H, W, 3), uint8) answering ``queries`` (their indices in
        :attr:`Detection.query`), best first."""
        ...


class OwlDetector:
    """A :class:`Detector` running OWLv2 (``Owlv2ForObjectDetection``) on the CPU.

    Args:
        model: the loaded ``Owlv2ForObjectDetection``.
        tokenizer: its text tokenizer (CLIP's).
        threshold: minimum score in [0, 1] of a reported box.
        nms_iou: boxes of one query overlapping a better one by more than this are dropped.
        max_per_query: at most this many boxes per query.
        image_mean, image_std: per-channel normalisation of images scaled to [0, 1].
    """

    def __init__(self, model: Any, tokenizer: Any, *, threshold: float = 0.1,
                 nms_iou: float = 0.3, max_per_query: int = 5,
                 image_mean: Sequence[float] = CLIP_MEAN,
                 image_std: Sequence[float] = CLIP_STD) -> None:
        if not 0.0 <= threshold <= 1.0:
            raise ConfigError(f"OwlDetector.threshold must be in [0, 1]; got {threshold!r}")
        if not 0.0 < nms_iou <= 1.0:
            raise ConfigError(f"OwlDetector.nms_iou must be in (0, 1]; got {nms_iou!r}")
        if max_per_query < 1:
            raise ConfigError(f"OwlDetector.max_per_query must be >= 1; got {max_per_query!r}")
        self.model = model
        self.tokenizer = tokenizer
        self.threshold = float(threshold)
        self.nms_iou = float(nms_iou)
        self.max_per_query = int(max_per_query)
        self.image_mean = np.asarray(image_mean, dtype=np.float32)
        self.image_std = np.asarray(image_std, dtype=np.float32)
        self.image_size = int(model.config.vision_config.image_size)
        self.text_length = int(model.config.text_config.max_position_embeddings)

    @classmethod
    def from_pretrained(cls, source: str | Path, **kwargs: Any) -> OwlDetector:
        """The detector with the model and tokenizer saved at ``source`` (a directory, or a
        model id in the local Hugging Face cache; nothing is downloaded); ``kwargs`` as for the
        constructor.

        Raises:
            ConfigError: no OWLv2 model (or no tokenizer) is at ``source``.
        """
        model = load_model(source, "Owlv2ForObjectDetection")
        mean, std = image_stats(source, CLIP_MEAN, CLIP_STD)
        kwargs.setdefault("image_mean", mean)
        kwargs.setdefault("image_std", std)
        return cls(model, load_tokenizer(source), **kwargs)

    def pixel_values(self, rgb: NDArray[np.uint8]) -> Any:
        """The model input of ``rgb`` (shape (H, W, 3)): a tensor of shape (1, 3, S, S), S the
        model's image size; the image padded to a max(H, W) square (bottom/right, grey 0.5)."""
        torch = require("torch")
        h, w = rgb.shape[:2]
        side = max(h, w)
        square = np.full((side, side, 3), 0.5, dtype=np.float32)
        square[:h, :w] = rgb.astype(np.float32) / 255.0
        image = torch.from_numpy(square).permute(2, 0, 1)[None]
        image = torch.nn.functional.interpolate(image, size=(self.image_size, self.image_size),
                                                mode="bilinear", antialias=True,
                                                align_corners=False)
        mean = torch.from_numpy(self.image_mean).view(1, 3, 1, 1)
        std = torch.from_numpy(self.image_std).view(1, 3, 1, 1)
        return (image - mean) / std

    def detect(self, rgb: NDArray[np.uint8], queries: Sequence[str]) -> list[Detection]:
        """Boxes scoring at least ``threshold`` for one of ``queries``, best first (pixel xyxy
        in ``rgb``'s frame, clipped to the image; each box answers its best-scoring query)."""
        if not queries:
            return []
        torch = require("torch")
        tokens = self.tokenizer(list(queries), padding="max_length", truncation=True,
                                max_length=self.text_length, return_tensors="pt")
        with torch.no_grad():
            out = self.model(input_ids=tokens["input_ids"],
                             attention_mask=tokens["attention_mask"],
                             pixel_values=self.pixel_values(rgb))
        probs = torch.sigmoid(out.logits[0]).numpy().astype(np.float64)  # (P, Q)
        boxes = _pixel_boxes(out.pred_boxes[0].numpy().astype(np.float64), rgb.shape[:2])
        query = probs.argmax(axis=1)
        score = probs[np.arange(len(query)), query]
        found: list[Detection] = []
        for q in range(len(queries)):
            idx = np.flatnonzero((query == q) & (score >= self.threshold)
                                 & np.all(boxes[:, 2:] > boxes[:, :2], axis=1))
            kept = idx[non_max_suppression(boxes[idx], score[idx], self.nms_iou)]
            found += [Detection(boxes[k].copy(), float(score[k]), q)
                      for k in kept[:self.max_per_query]]
        return sorted(found, key=lambda d: -d.score)


def _pixel_boxes(cxcywh: NDArray[np.float64], shape: tuple[int, ...]) -> NDArray[np.float64]:
    """Pixel xyxy boxes, shape (P, 4), of OWLv2's normalised (cx, cy, w, h) boxes, shape (P, 4),
    which are relative to the padded max(H, W) square; clipped to the H x W image."""
    h, w = int(shape[0]), int(shape[1])
    side = float(max(h, w))
    c, size = cxcywh[:, :2], cxcywh[:, 2:]
    xyxy = np.concatenate([c - size / 2.0, c + size / 2.0], axis=1) * side
    return np.clip(xyxy, 0.0, [w, h, w, h])
