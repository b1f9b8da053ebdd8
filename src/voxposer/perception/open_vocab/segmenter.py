"""Box-prompted segmentation: a boolean mask per box (Segment Anything).

The paper feeds each detector box to SAM to get the object's mask. :class:`Segmenter` is the
seam; :class:`SamSegmenter` wraps ``transformers``' ``SamModel`` with its own preprocessing: the
image's longer side is resized to the model's input size, normalised and zero-padded at its bottom
and right to a square; the image is encoded once for all of its boxes.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, Final, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.perception.open_vocab.weights import image_stats, load_model, require

#: ImageNet per-channel normalisation of images in [0, 1] (SAM's default).
IMAGENET_MEAN: Final = (0.485, 0.456, 0.406)
IMAGENET_STD: Final = (0.229, 0.224, 0.225)


@runtime_checkable
class Segmenter(Protocol):
    """Turns box prompts into object masks."""

    def segment(self, rgb: NDArray[np.uint8], boxes: ArrayLike) -> NDArray[np.bool_]:
        """Masks, shape (K, H, W), of the objects in ``rgb`` (shape (H, W, 3), uint8) inside the
        pixel xyxy ``boxes``, shape (K, 4)."""
        ...


class SamSegmenter:
    """A :class:`Segmenter` running Segment Anything (``SamModel``) on the CPU.

    Args:
        model: the loaded ``SamModel``.
        mask_threshold: a pixel belongs to the mask where the mask logit exceeds this.
        image_mean, image_std: per-channel normalisation of images scaled to [0, 1].
    """

    def __init__(self, model: Any, *, mask_threshold: float = 0.0,
                 image_mean: Sequence[float] = IMAGENET_MEAN,
                 image_std: Sequence[float] = IMAGENET_STD) -> None:
        self.model = model
        self.mask_threshold = float(mask_threshold)
        self.image_mean = np.asarray(image_mean, dtype=np.float32)
        self.image_std = np.asarray(image_std, dtype=np.float32)
        self.image_size = int(model.config.vision_config.image_size)

    @classmethod
    def from_pretrained(cls, source: str | Path, **kwargs: Any) -> SamSegmenter:
        """The segmenter with the ``SamModel`` saved at ``source`` (a directory, or a model id
        in the local Hugging Face cache; nothing is downloaded).

        Raises:
            ConfigError: no SAM model is at ``source``.
        """
        model = load_model(source, "SamModel")
        mean, std = image_stats(source, IMAGENET_MEAN, IMAGENET_STD)
        kwargs.setdefault("image_mean", mean)
        kwargs.setdefault("image_std", std)
        return cls(model, **kwargs)

    def _scale(self, shape: tuple[int, ...]) -> tuple[float, int, int]:
        """The resize factor of an (H, W) image and its resized height and width [px]."""
        scale = self.image_size / max(shape[0], shape[1])
        return scale, round(shape[0] * scale), round(shape[1] * scale)

    def pixel_values(self, rgb: NDArray[np.uint8]) -> Any:
        """The model input of ``rgb`` (shape (H, W, 3)): a tensor of shape (1, 3, S, S)."""
        torch = require("torch")
        _, h, w = self._scale(rgb.shape)
        image = torch.from_numpy(rgb.astype(np.float32) / 255.0).permute(2, 0, 1)[None]
        image = torch.nn.functional.interpolate(image, size=(h, w), mode="bilinear",
                                                antialias=True, align_corners=False)
        mean = torch.from_numpy(self.image_mean).view(1, 3, 1, 1)
        std = torch.from_numpy(self.image_std).view(1, 3, 1, 1)
        padded = torch.zeros((1, 3, self.image_size, self.image_size))
        padded[:, :, :h, :w] = (image - mean) / std
        return padded

    def segment(self, rgb: NDArray[np.uint8], boxes: ArrayLike) -> NDArray[np.bool_]:
        """One mask per box, shape (K, H, W): SAM's single-mask output for each box prompt,
        upsampled to the image and thresholded at ``mask_threshold``."""
        torch = require("torch")
        height, width = rgb.shape[:2]
        b = np.asarray(boxes, dtype=np.float64).reshape(-1, 4)
        if len(b) == 0:
            return np.zeros((0, height, width), dtype=bool)
        scale, h, w = self._scale(rgb.shape)
        prompts = torch.from_numpy((b * scale).astype(np.float32))[None]  # (1, K, 4)
        with torch.no_grad():
            embeddings = self.model.get_image_embeddings(self.pixel_values(rgb))
            out = self.model(image_embeddings=embeddings, input_boxes=prompts,
                             multimask_output=False)
            logits = out.pred_masks[0, :, 0]  # (K, m, m), over the padded square
            size = (self.image_size, self.image_size)
            full = torch.nn.functional.interpolate(logits[:, None], size=size,
                                                   mode="bilinear", align_corners=False)
            full = torch.nn.functional.interpolate(full[:, :, :h, :w], size=(height, width),
                                                   mode="bilinear", align_corners=False)
        return (full[:, 0] > self.mask_threshold).numpy()
