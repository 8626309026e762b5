"""The thermal video's false colour: a fixed palette mapping a fixed temperature span to colours, so
that a colour means the same temperature in every frame of every run (an automatic gain, stretching
each frame to its own minimum and maximum, would make the ambient ground flicker as a fire enters and
leaves the view). Sans-IO: temperatures in, RGB bytes out.

The span is SPAN_C: 0 C black, 100 C white. Ambient ground (10-30 C) is dark purple, the model's fires
(tens of degrees above it) magenta to orange, anything at or above 100 C white; the sky (-20 C) and
anything below 0 C black. The colours run as an "iron" palette does (black, purple, magenta, orange,
yellow, white), and their brightness rises all the way along it, so a hotter pixel is never darker.
"""
from __future__ import annotations

import numpy as np

SPAN_C = (0.0, 100.0)  # the temperatures at the palette's two ends [deg C]
# (position along the palette 0..1, R, G, B): the iron palette's turning points
ANCHORS = ((0.00, 0, 0, 0), (0.20, 40, 0, 110), (0.45, 170, 0, 140), (0.70, 240, 100, 10),
           (0.88, 255, 215, 0), (1.00, 255, 255, 255))
LEVELS = 256


def _table() -> np.ndarray:
    at = np.linspace(0.0, 1.0, LEVELS)
    where = np.array([a[0] for a in ANCHORS])
    channels = [np.interp(at, where, np.array([a[k] for a in ANCHORS], dtype=float)) for k in (1, 2, 3)]
    table = np.rint(np.stack(channels, axis=-1)).astype(np.uint8)
    table.setflags(write=False)
    return table


TABLE = _table()  # (LEVELS, 3) uint8: the colour of each level


def levels(image_c: np.ndarray, span_c: tuple[float, float] = SPAN_C) -> np.ndarray:
    """Each pixel's level 0..255 along the palette (NaN, below the span: 0; above it: 255)."""
    low, high = span_c
    scaled = (np.nan_to_num(image_c, nan=low) - low) * ((LEVELS - 1) / (high - low))
    return np.clip(np.rint(scaled), 0, LEVELS - 1).astype(np.uint8)


def colour(image_c: np.ndarray, span_c: tuple[float, float] = SPAN_C) -> np.ndarray:
    """A (height, width) image of temperatures [deg C] as a (height, width, 3) RGB uint8 frame."""
    return TABLE[levels(image_c, span_c)]


def luminance(rgb: np.ndarray) -> np.ndarray:
    """Rec. 601 luma of RGB values (what H.264's Y plane carries), 0..255."""
    rgb = np.asarray(rgb, dtype=float)
    return 0.299 * rgb[..., 0] + 0.587 * rgb[..., 1] + 0.114 * rgb[..., 2]
