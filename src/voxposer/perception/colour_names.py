"""Colour words → pixels: hue/saturation thresholds for each of the catalog's named colours.

A colour detector's vocabulary: the nominal paint colour of each colour word
(:data:`voxposer.catalog.COLOR_NAMES`). Under white light a matte surface keeps its paint's hue
and saturation however brightly it is lit; only its value (brightness) changes. So a pixel is
called colour ``c`` when its hue and saturation lie close to ``c``'s paint and it is not too dark
to judge. The achromatic colour ("gray") only says "no hue": the robot, too, is gray, and
telling a gray block from the robot is left to geometry
(:mod:`voxposer.perception.colour_objects`).

No segmentation channel, no simulator state: RGB in, a colour index per pixel out.
"""

from __future__ import annotations

from typing import Final

import numpy as np
from numpy.typing import NDArray

from voxposer.catalog import COLOR_NAMES

#: Nominal paint colour (RGB in [0, 1]) of each colour word, in :data:`COLOR_NAMES` order. A
#: real camera rig would calibrate these under its own lights.
PAINT_RGB: Final[tuple[tuple[float, float, float], ...]] = (
    (0.12, 0.30, 0.85),  # blue
    (0.15, 0.65, 0.20),  # green
    (0.95, 0.85, 0.10),  # yellow
    (0.98, 0.55, 0.75),  # pink
    (0.50, 0.30, 0.12),  # brown
    (0.85, 0.10, 0.10),  # red
    (1.00, 0.50, 0.05),  # orange
    (0.50, 0.15, 0.70),  # purple
    (0.10, 0.85, 0.90),  # cyan
    (0.50, 0.50, 0.50),  # gray
)
#: Index of the achromatic colour word in :data:`COLOR_NAMES`.
GRAY: Final = COLOR_NAMES.index("gray")
#: A pixel matches a chromatic colour within this hue distance [deg] …
HUE_TOLERANCE_DEG: Final = 8.0
#: … and this saturation difference (saturation in [0, 1]).
SATURATION_TOLERANCE: Final = 0.08
#: Saturated pixels (value at least this) lose saturation and drift in hue where a channel clips
#: (a bright paint in strong light: pink) …
CLIPPED_VALUE: Final = 0.98
#: … so there the hue tolerance [deg] and the saturation allowed below the paint's widen.
CLIPPED_HUE_TOLERANCE_DEG: Final = 14.0
CLIPPED_SATURATION_DROP: Final = 0.15
#: Pixels darker than this value (in [0, 1]) carry no usable colour.
MIN_VALUE: Final = 0.08
#: A pixel with saturation below this is achromatic (gray, white, black).
ACHROMATIC_SATURATION: Final = 0.03
#: Label of a pixel that matches no colour word.
NO_COLOUR: Final = -1


def rgb_to_hsv(rgb: NDArray[np.uint8]) -> NDArray[np.float32]:
    """Hue [deg, 0–360), saturation [0, 1] and value [0, 1] of an image, shape (H, W, 3) (or
    (N, 3)) of uint8 RGB; same leading shape out, float32."""
    c = rgb.astype(np.float32) / 255.0
    r, g, b = c[..., 0], c[..., 1], c[..., 2]
    hi, lo = c.max(axis=-1), c.min(axis=-1)
    span = hi - lo
    safe = np.where(span > 0, span, 1.0)
    hue = np.where(hi == r, (g - b) / safe % 6.0,
                   np.where(hi == g, (b - r) / safe + 2.0, (r - g) / safe + 4.0)) * 60.0
    hue = np.where(span > 0, hue, 0.0)
    sat = np.where(hi > 0, span / np.where(hi > 0, hi, 1.0), 0.0)
    return np.stack([hue, sat, hi], axis=-1).astype(np.float32)


def _paint_hsv() -> NDArray[np.float32]:
    paint = np.round(np.asarray(PAINT_RGB) * 255).astype(np.uint8)
    return rgb_to_hsv(paint)


#: Memo entry of an RGB value not classified yet.
_UNKNOWN: Final = -2
#: RGB value (packed ``r << 16 | g << 8 | b``) → its colour word, filled as values are met
#: (16 MiB, made on first use; a pixel's word depends on its RGB value alone).
_memo: list[NDArray[np.int8]] = []


def colour_labels(rgb: NDArray[np.uint8]) -> NDArray[np.int32]:
    """The colour word of every pixel of ``rgb`` (shape (..., 3), uint8: an image (H, W, 3) or
    pixels (N, 3)) as an index into :data:`COLOR_NAMES`, shape (...), int32; :data:`NO_COLOUR`
    where none fits.

    Chromatic words: nearest paint in hue among those within :data:`HUE_TOLERANCE_DEG` and
    :data:`SATURATION_TOLERANCE` (wider where a channel clips: :data:`CLIPPED_VALUE`). "gray":
    any achromatic pixel that is not too dark. Each RGB value is classified once per process
    (:func:`classify_colours`) and remembered, so a frame of colours met before costs a lookup.
    """
    flat = np.asarray(rgb, dtype=np.uint8).reshape(-1, 3)
    if not _memo:
        _memo.append(np.full(1 << 24, _UNKNOWN, dtype=np.int8))
    memo = _memo[0]
    packed = (flat[:, 0].astype(np.int32) << 16) | (flat[:, 1].astype(np.int32) << 8) | flat[:, 2]
    words = memo[packed]
    missing = words == _UNKNOWN
    if missing.any():
        keys = np.unique(packed[missing])
        values = np.stack([keys >> 16, (keys >> 8) & 255, keys & 255], axis=1).astype(np.uint8)
        memo[keys] = classify_colours(values)
        words = memo[packed]
    return words.astype(np.int32).reshape(np.shape(rgb)[:-1])


def classify_colours(rgb: NDArray[np.uint8]) -> NDArray[np.int32]:
    """:func:`colour_labels` computed afresh for every pixel (no memo): ``rgb`` shape (..., 3)
    uint8 → shape (...) int32."""
    hsv = rgb_to_hsv(rgb)
    hue, sat, val = hsv[..., 0], hsv[..., 1], hsv[..., 2]
    paint = _paint_hsv()
    out = np.full(hue.shape, NO_COLOUR, dtype=np.int32)
    best = np.full(hue.shape, np.inf, dtype=np.float32)
    lit = val >= MIN_VALUE
    clipped = val >= CLIPPED_VALUE
    hue_tol = np.where(clipped, CLIPPED_HUE_TOLERANCE_DEG, HUE_TOLERANCE_DEG)
    drop = np.where(clipped, CLIPPED_SATURATION_DROP, 0.0) + SATURATION_TOLERANCE
    for k, (p_hue, p_sat, _) in enumerate(paint):
        if k == GRAY:
            continue
        dh = np.abs((hue - p_hue + 180.0) % 360.0 - 180.0)
        fits = lit & (dh <= hue_tol) & (sat >= p_sat - drop) & (sat <= p_sat + SATURATION_TOLERANCE)
        closer = fits & (dh < best)
        out[closer], best[closer] = k, dh[closer]
    out[lit & (sat < ACHROMATIC_SATURATION)] = GRAY
    return out


__all__ = ["GRAY", "NO_COLOUR", "PAINT_RGB", "classify_colours", "colour_labels", "rgb_to_hsv"]
