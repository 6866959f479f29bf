# SPDX-License-Identifier: Apache-2.0
"""Shading a raster: the shader interface, the frame a shader's pixels end up in, and its costs.

Owns ``Shader`` with what it gets and returns (``ShadeContext``, ``ShadeResult``, ``per_span``),
``shade`` (run a shader over a ``Raster``, keep the depth-test winners), ``render``
(``shade(rasterise(scene), shader)``), ``Frame`` and ``RenderStats``.  May import numpy, tqdm and
``model.render`` ``scene``, ``vectors``, ``spans`` and ``raster``.

The shader interface: a ``Shader`` is any callable ``shader(spans, ctx)`` taking the ``Spans`` of
one object (structure of arrays, one row per span) and a ``ShadeContext``, returning either a
``(spans.n_pixels, 3)`` uint8 array (the pixels of span i are rows ``spans.offsets[i] :
spans.offsets[i+1]``, left to right) or a ``ShadeResult`` (the same plus an optional float
specular term per pixel and cost counters).  ``per_span(fn)`` turns a function of one ``Span``
into such a shader.  A bit-exact unit shader looks like::

    def hybrid(spans: Spans, ctx: ShadeContext) -> ShadeResult:
        rgb = np.empty((spans.n_pixels, 3), dtype=np.uint8)
        for i in range(len(spans)):
            lo, hi = spans.offsets[i], spans.offsets[i + 1]
            l = spans.x_end[i] - spans.x_start[i]         # intervals (pixels - 1)
            # Gouraud: spans.g_start[i], spans.g_end[i] (RGB levels) -> divider -> gouraud unit
            # specular: spans.n_start[i], spans.h_start[i], spans.n_end[i], spans.h_end[i], l,
            #           ctx.material.n, C = 255 * ctx.material.k_s * ctx.lighting.intensity
            rgb[lo:hi] = ...                               # summed and saturated, uint8
        return ShadeResult(rgb, counters={"specular_cycles": ...})
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, fields

import numpy as np
from numba import njit

from model.render.raster import Raster, rasterise
from model.render.scene import Material, Scene
from model.render.spans import Span, Spans
from model.render.vectors import LightingParams

# ------------------------------------------------------------------------------------------------
# shading


@dataclass(frozen=True, eq=False)
class ShadeContext:
    """What a shader gets besides the spans: the scene, which object, its material, the lighting
    parameters, and whether a progress bar is wanted."""

    scene: Scene
    obj: int
    material: Material
    lighting: LightingParams
    progress: bool = False


@dataclass(frozen=True, eq=False)
class ShadeResult:
    """A shader's output for the spans of one object.

    ``rgb`` (n_pixels, 3) uint8 final pixel values; ``specular`` (n_pixels,) float, optional: the
    specular term in levels (the reference shaders fill it; it defines the highlight mask);
    ``counters``: cost counters (e.g. unit cycles), summed over objects into ``RenderStats``.
    """

    rgb: np.ndarray
    specular: np.ndarray | None = None
    counters: dict[str, float] = field(default_factory=dict)


Shader = Callable[[Spans, ShadeContext], "np.ndarray | ShadeResult"]


def per_span(
    fn: Callable[[Span, ShadeContext], np.ndarray | ShadeResult], desc: str = "spans"
) -> Shader:
    """A ``Shader`` from a function of one ``Span`` returning its ``(length, 3)`` uint8 pixels
    (or a ``ShadeResult`` for those pixels).  Shows a tqdm progress bar when ``ctx.progress``."""

    def shader(spans: Spans, ctx: ShadeContext) -> ShadeResult:
        from tqdm import tqdm

        rgb = np.empty((spans.n_pixels, 3), dtype=np.uint8)
        spec = None
        counters: dict[str, float] = {}
        it = range(len(spans))
        if ctx.progress:
            it = tqdm(it, desc=desc, unit="span", leave=False, mininterval=0.5)
        for i in it:
            lo, hi = spans.offsets[i], spans.offsets[i + 1]
            res = _as_result(fn(spans.span(i), ctx), int(hi - lo))
            rgb[lo:hi] = res.rgb
            if res.specular is not None:
                if spec is None:
                    spec = np.zeros(spans.n_pixels)
                spec[lo:hi] = res.specular
            for k, v in res.counters.items():
                counters[k] = counters.get(k, 0) + v
        return ShadeResult(rgb, spec, counters)

    shader.__name__ = getattr(fn, "__name__", "per_span_shader")
    return shader


def _as_result(out, n_pixels: int) -> ShadeResult:
    res = out if isinstance(out, ShadeResult) else ShadeResult(np.asarray(out))
    rgb = np.asarray(res.rgb)
    if rgb.shape != (n_pixels, 3):
        raise ValueError(
            f"shader output shape = {rgb.shape} is not legal: legal shape is ({n_pixels}, 3)"
        )
    if rgb.dtype != np.uint8:
        raise ValueError(f"shader output dtype = {rgb.dtype} is not legal: legal dtype is uint8")
    if res.specular is not None and np.shape(res.specular) != (n_pixels,):
        raise ValueError(
            f"shader specular shape = {np.shape(res.specular)} is not legal: legal is ({n_pixels},)"
        )
    return ShadeResult(rgb, res.specular, dict(res.counters))


@dataclass(frozen=True)
class RenderStats:
    """What the frame needed.  ``pixels_shaded`` counts every pixel of every span sent through
    the shader (hidden pixels of partly visible spans included); ``pixels_covered`` the pixels
    in the final image.  ``longest_span`` is over the shaded spans, ``n_values`` the exponents of
    the objects that had a shaded span."""

    triangles: int
    triangles_culled: int
    triangles_clipped: int
    triangles_shaded: int  # triangles with at least one shaded span
    spans: int  # all spans, hidden ones included
    spans_shaded: int
    pixels_shaded: int
    pixels_covered: int
    longest_span: int
    n_values: tuple[int, ...]
    counters: dict[str, float]
    raster_seconds: float
    shade_seconds: float

    @property
    def pixels_per_second(self) -> float:
        """Shaded pixels per second of shading (the rasterisation excluded)."""
        return self.pixels_shaded / self.shade_seconds if self.shade_seconds > 0 else float("inf")

    @property
    def total_pixels_per_second(self) -> float:
        total = self.raster_seconds + self.shade_seconds
        return self.pixels_shaded / total if total > 0 else float("inf")

    def as_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True, eq=False)
class Frame:
    """A rendered image.  ``rgb`` (H, W, 3) uint8; ``obj_id`` / ``tri_id`` (H, W) int64: the
    object and the triangle (index in its mesh) seen at each pixel, -1 for background;
    ``specular`` (H, W) float levels when the shader provided them (else None)."""

    rgb: np.ndarray
    obj_id: np.ndarray
    tri_id: np.ndarray
    specular: np.ndarray | None
    stats: RenderStats

    @property
    def coverage(self) -> np.ndarray:
        """(H, W) bool: pixels covered by some triangle."""
        return self.obj_id >= 0


_NO_SPEC = np.zeros(0)
_NO_FRAME_SPEC = np.zeros((0, 0))


@njit(cache=True)
def _scatter(
    y, x_start, offsets, vis, src_rgb, tri, obj, has_spec, src_spec, rgb, obj_id, tri_id, spec
):
    """The visible pixels of one object's spans into the frame: RGB, object and triangle ids,
    the specular term (if ``has_spec``).  Returns how many were not covered yet."""
    new = 0
    for s in range(y.size):
        row = y[s]
        for p in range(offsets[s], offsets[s + 1]):
            if vis[p]:
                x = x_start[s] + p - offsets[s]
                for c in range(3):
                    rgb[row, x, c] = src_rgb[p, c]
                if obj_id[row, x] < 0:
                    new += 1
                obj_id[row, x] = obj
                tri_id[row, x] = tri[s]
                if has_spec:
                    spec[row, x] = src_spec[p]
    return new


def shade(
    raster: Raster, shader: Shader, *, skip_hidden_spans: bool = True, progress: bool = False
) -> Frame:
    """Run ``shader`` over the spans of every object and assemble the frame (depth-tested)."""
    t0 = time.perf_counter()
    scene = raster.scene
    cam = scene.camera
    params = LightingParams.of(scene)
    rgb = np.empty((cam.height, cam.width, 3), dtype=np.uint8)
    # One row of background pixels, copied to every row (a fill by a (3,) pattern is slow).
    row = np.tile(np.asarray(scene.background, dtype=np.uint8), cam.width)
    rgb.reshape(cam.height, cam.width * 3)[:] = row
    obj_id = np.full((cam.height, cam.width), -1, dtype=np.int64)
    tri_id = np.full((cam.height, cam.width), -1, dtype=np.int64)
    specular = None
    counters: dict[str, float] = {}
    spans_shaded = pixels_shaded = longest = pixels_covered = 0
    triangles_shaded = 0
    n_values: set[int] = set()
    for orast in raster.objects:
        sp = orast.spans
        if skip_hidden_spans:
            pick = orast.visible_per_span > 0
            sub = sp.select(pick)
            vis = orast.visible[np.repeat(pick, sp.lengths)]
        else:
            sub, vis = sp, orast.visible
        if len(sub) == 0:
            continue
        material = scene.objects[sp.obj].material
        ctx = ShadeContext(scene, sp.obj, material, params, progress)
        res = _as_result(shader(sub, ctx), sub.n_pixels)
        if res.specular is not None and specular is None:
            specular = np.zeros((cam.height, cam.width))
        has_spec = res.specular is not None
        pixels_covered += _scatter(
            sub.y, sub.x_start, sub.offsets, vis, np.ascontiguousarray(res.rgb), sub.tri, sp.obj,
            has_spec, np.asarray(res.specular if has_spec else _NO_SPEC, dtype=np.float64),
            rgb, obj_id, tri_id, specular if specular is not None else _NO_FRAME_SPEC,
        )  # fmt: skip
        for k, v in res.counters.items():
            counters[k] = counters.get(k, 0) + v
        spans_shaded += len(sub)
        pixels_shaded += sub.n_pixels
        longest = max(longest, int(sub.lengths.max()))
        triangles_shaded += int(np.count_nonzero(np.bincount(sub.tri)))
        n_values.add(material.n)
    stats = RenderStats(
        triangles=sum(o.triangles for o in raster.objects),
        triangles_culled=sum(o.triangles_culled for o in raster.objects),
        triangles_clipped=sum(o.triangles_clipped for o in raster.objects),
        triangles_shaded=triangles_shaded,
        spans=sum(len(o.spans) for o in raster.objects),
        spans_shaded=spans_shaded,
        pixels_shaded=pixels_shaded,
        pixels_covered=pixels_covered,
        longest_span=longest,
        n_values=tuple(sorted(n_values)),
        counters=counters,
        raster_seconds=raster.seconds,
        shade_seconds=time.perf_counter() - t0,
    )
    return Frame(rgb, obj_id, tri_id, specular, stats)


def render(
    scene: Scene,
    shader: Shader,
    *,
    cull_backfaces: bool = True,
    skip_hidden_spans: bool = True,
    progress: bool = False,
) -> Frame:
    """Rasterise ``scene`` and shade it with ``shader``: ``shade(rasterise(scene), shader)``."""
    raster = rasterise(scene, cull_backfaces=cull_backfaces)
    return shade(raster, shader, skip_hidden_spans=skip_hidden_spans, progress=progress)
