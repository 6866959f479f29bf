# SPDX-License-Identifier: Apache-2.0
"""Image accuracy metrics against a reference image (method (a), exact Blinn).

All metrics work on 8-bit images ((H, W, 3) uint8, or any array of 0..255 values), converted to
float64, over all three channels of the selected pixels (all pixels unless ``mask`` is given):

* ``nmse`` -- the thesis's normalised mean square error
  ``NMSE = sum((img - ref)^2) / sum(ref^2)``; the thesis (Romanyuk 2009; docs/scenes.md)
  treats ``NMSE <= 0.00025`` (``NMSE_VISUALLY_IDENTICAL``) as visually identical.
* ``psnr`` -- ``10 log10(255^2 / MSE)`` dB, MSE the mean of ``(img - ref)^2`` (inf if equal).
* ``max_abs_error`` -- the largest ``|img - ref|`` in 8-bit levels.
* ``share_off_by_more_than`` -- the fraction of *pixels* with some channel off by more than
  ``levels`` (default 1) levels.
* ``highlight_mask`` -- pixels where the reference's specular term exceeds ``threshold`` levels;
  ``compare(..., highlight=mask)`` reports the same metrics restricted to it.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

NMSE_VISUALLY_IDENTICAL = 0.00025
"""The thesis's threshold: NMSE at or below it counts as visually identical."""


def _pair(img, ref, mask=None) -> tuple[np.ndarray, np.ndarray]:
    a = np.asarray(img, dtype=np.float64)
    b = np.asarray(ref, dtype=np.float64)
    if a.shape != b.shape:
        raise ValueError(
            f"image shape = {a.shape} is not legal: must equal the reference {b.shape}"
        )
    if mask is not None:
        m = np.asarray(mask, dtype=bool)
        if m.shape != a.shape[: m.ndim] or m.ndim == 0:
            raise ValueError(
                f"mask shape = {m.shape} is not legal: legal is the image's leading shape "
                f"{a.shape[:2]}"
            )
        a, b = a[m], b[m]
    return a, b


def nmse(img, ref, mask=None) -> float:
    """``sum((img - ref)^2) / sum(ref^2)`` over all channels (of the masked pixels).

    0 for identical images; if the reference is all zero, 0 when img is too, else inf."""
    a, b = _pair(img, ref, mask)
    num = float(np.sum((a - b) ** 2))
    den = float(np.sum(b**2))
    if den == 0.0:
        return 0.0 if num == 0.0 else math.inf
    return num / den


def mse(img, ref, mask=None) -> float:
    a, b = _pair(img, ref, mask)
    return float(np.mean((a - b) ** 2)) if a.size else 0.0


def psnr(img, ref, mask=None, peak: float = 255.0) -> float:
    """Peak signal-to-noise ratio in dB: ``10 log10(peak^2 / MSE)``; inf when MSE = 0."""
    m = mse(img, ref, mask)
    return math.inf if m == 0.0 else 10.0 * math.log10(peak * peak / m)


def max_abs_error(img, ref, mask=None) -> float:
    a, b = _pair(img, ref, mask)
    return float(np.max(np.abs(a - b))) if a.size else 0.0


def share_off_by_more_than(img, ref, levels: float = 1.0, mask=None) -> float:
    """Fraction of pixels (of the masked pixels) with any channel off by more than ``levels``."""
    a, b = _pair(img, ref, mask)
    if a.size == 0:
        return 0.0
    err = np.abs(a - b)
    per_pixel = err.max(axis=-1) if err.ndim >= 2 and err.shape[-1] == 3 else err
    return float(np.mean(per_pixel > levels))


def highlight_mask(specular, threshold: float = 8.0) -> np.ndarray:
    """(H, W) bool: pixels where the reference's specular term exceeds ``threshold`` levels."""
    if specular is None:
        raise ValueError("specular = None is not legal: render the reference with its specular")
    return np.asarray(specular, dtype=np.float64) > threshold


@dataclass(frozen=True)
class Comparison:
    """Accuracy of one image against the reference (see the module doc for definitions)."""

    nmse: float
    psnr: float
    max_abs_error: float
    share_off_by_more_than_1: float
    visually_identical: bool  # nmse <= NMSE_VISUALLY_IDENTICAL
    highlight_pixels: int
    highlight_nmse: float  # nan when there is no highlight mask or it is empty
    highlight_max_abs_error: float
    highlight_mean_abs_error: float

    def as_dict(self) -> dict:
        return asdict(self)


def compare(img, ref, highlight=None, mask=None) -> Comparison:
    """All metrics of ``img`` against ``ref``; ``highlight`` an (H, W) bool mask for the
    highlight figures; ``mask`` restricts the whole-image figures (default: every pixel)."""
    value = nmse(img, ref, mask)
    if highlight is not None and np.any(highlight):
        a, b = _pair(img, ref, highlight)
        h_pixels = int(np.count_nonzero(highlight))
        h_nmse = nmse(img, ref, highlight)
        h_max = float(np.max(np.abs(a - b)))
        h_mean = float(np.mean(np.abs(a - b)))
    else:
        h_pixels = 0 if highlight is None else int(np.count_nonzero(highlight))
        h_nmse = h_max = h_mean = math.nan
    return Comparison(
        nmse=value,
        psnr=psnr(img, ref, mask),
        max_abs_error=max_abs_error(img, ref, mask),
        share_off_by_more_than_1=share_off_by_more_than(img, ref, 1.0, mask),
        visually_identical=value <= NMSE_VISUALLY_IDENTICAL,
        highlight_pixels=h_pixels,
        highlight_nmse=h_nmse,
        highlight_max_abs_error=h_max,
        highlight_mean_abs_error=h_mean,
    )
