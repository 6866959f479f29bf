# SPDX-License-Identifier: Apache-2.0
"""Spans: what the rasteriser hands a shader, one scan-line segment of one triangle per row.

Owns ``Span`` (one span as the hardware set-up sees it), ``Spans`` (the spans of one object as a
structure of arrays, with the ``offsets`` of each span's pixels in a flat per-pixel array) and
``SPAN_ARRAYS``, the names of the per-span arrays a ``Spans`` holds.  May import numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

# ------------------------------------------------------------------------------------------------
# spans


@dataclass(frozen=True, eq=False)
class Span:
    """One span (scan-line segment of one triangle), as the hardware set-up sees it.

    Pixels ``x_start..x_end`` (inclusive) of row ``y``; ``length`` = x_end - x_start + 1 pixels,
    ``intervals`` = length - 1 (the patent's l).  ``*_start`` / ``*_end`` are the values at the
    first and the last pixel centre.  Intensities in 8-bit levels.
    """

    y: int
    x_start: int
    x_end: int
    obj: int  # object index in the scene
    tri: int  # triangle index in the object's mesh
    n_start: np.ndarray  # (3,) unit normal, spherically interpolated
    n_end: np.ndarray
    h_start: np.ndarray  # (3,) unit half-vector at the span end's world position
    h_end: np.ndarray
    nlin_start: np.ndarray  # (3,) linearly interpolated normal, not normalised (classic Phong)
    nlin_end: np.ndarray
    p_start: np.ndarray  # (3,) world position
    p_end: np.ndarray
    g_start: np.ndarray  # (3,) Gouraud ambient + diffuse RGB in levels (vertex-lit, linear)
    g_end: np.ndarray
    s_start: float  # specular lit at the vertices, linearly interpolated, in levels
    s_end: float
    z_start: float  # camera-space depth
    z_end: float

    @property
    def length(self) -> int:
        return self.x_end - self.x_start + 1

    @property
    def intervals(self) -> int:
        return self.x_end - self.x_start


SPAN_ARRAYS = (
    "y",
    "x_start",
    "x_end",
    "tri",
    "n_start",
    "n_end",
    "h_start",
    "h_end",
    "nlin_start",
    "nlin_end",
    "p_start",
    "p_end",
    "g_start",
    "g_end",
    "s_start",
    "s_end",
    "z_start",
    "z_end",
)


@dataclass(frozen=True, eq=False)
class Spans:
    """The spans of one object, structure of arrays (one row per span, S rows).

    Integer arrays (S,): ``y``, ``x_start``, ``x_end``, ``tri``.  Float arrays: ``n_*``,
    ``h_*``, ``nlin_*``, ``p_*``, ``g_*`` (S, 3); ``s_*``, ``z_*`` (S,).  Field meanings as in
    ``Span``.  ``offsets`` (S+1,) locate each span's pixels in a flat per-pixel array.
    """

    obj: int
    y: np.ndarray
    x_start: np.ndarray
    x_end: np.ndarray
    tri: np.ndarray
    n_start: np.ndarray
    n_end: np.ndarray
    h_start: np.ndarray
    h_end: np.ndarray
    nlin_start: np.ndarray
    nlin_end: np.ndarray
    p_start: np.ndarray
    p_end: np.ndarray
    g_start: np.ndarray
    g_end: np.ndarray
    s_start: np.ndarray
    s_end: np.ndarray
    z_start: np.ndarray
    z_end: np.ndarray
    offsets: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        off = np.zeros(self.y.size + 1, dtype=np.int64)
        np.cumsum(self.x_end - self.x_start + 1, out=off[1:])
        object.__setattr__(self, "offsets", off)

    def __len__(self) -> int:
        return int(self.y.size)

    @property
    def lengths(self) -> np.ndarray:
        """Pixels per span."""
        return self.x_end - self.x_start + 1

    @property
    def n_pixels(self) -> int:
        return int(self.offsets[-1])

    def span(self, i: int) -> Span:
        kw = {name: getattr(self, name)[i] for name in SPAN_ARRAYS}
        for name in ("y", "x_start", "x_end", "tri"):
            kw[name] = int(kw[name])
        for name in ("s_start", "s_end", "z_start", "z_end"):
            kw[name] = float(kw[name])
        return Span(obj=self.obj, **kw)

    def select(self, mask_or_index: np.ndarray) -> Spans:
        """The subset of spans picked by a boolean mask or index array (order kept); a mask that
        picks every span gives these spans themselves."""
        pick = np.asarray(mask_or_index)
        if pick.dtype == bool:
            if pick.all():
                return self  # every span: the arrays are not copied (Spans are read-only)
            pick = np.flatnonzero(pick)
        kw = {name: getattr(self, name).take(pick, axis=0) for name in SPAN_ARRAYS}
        return Spans(obj=self.obj, **kw)

    def pixel_xy(self) -> tuple[np.ndarray, np.ndarray]:
        """Column and row of every pixel, flat (n_pixels,), in span order, left to right."""
        lengths = self.lengths
        ys = np.repeat(self.y, lengths)
        xs = np.repeat(self.x_start - self.offsets[:-1], lengths) + np.arange(self.n_pixels)
        return xs, ys

    def pixel_t(self) -> np.ndarray:
        """The per-pixel span parameter t = (x - x_start) / (x_end - x_start), 0 for 1-pixel
        spans, flat (n_pixels,)."""
        lengths = self.lengths
        k = np.arange(self.n_pixels) - np.repeat(self.offsets[:-1], lengths)
        return k / np.repeat(np.maximum(lengths - 1, 1), lengths).astype(np.float64)
