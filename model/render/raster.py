"""The float rasteriser: the "external device" of the patent that feeds the shading units.

``render(scene, shader)`` = ``shade(rasterise(scene), shader)``:

1. **Projection.**  World -> camera (``Camera.basis``) -> screen.  Screen x grows to the right,
   y downwards; pixel (x, y) has its centre at (x + 0.5, y + 0.5).  Triangles with a vertex at
   or behind the near plane (camera depth <= ``NEAR``) are dropped (no clipping: the built-in
   scenes keep the camera outside every mesh) and counted in ``RenderStats.triangles_clipped``.
   A drawn triangle with a corner beyond ``MAX_SCREEN_COORD`` (2**40) pixels is refused with a
   ``ValueError`` naming the object, the triangle and the vertex.
2. **Back faces.**  Default: culled.  A triangle is front-facing when its geometric normal
   (counter-clockwise winding) points towards the eye: ``((P1-P0) x (P2-P0)) . (eye-P0) > 0``.
   With ``cull_backfaces=False`` the renderer is two-sided: a back-facing triangle is drawn with
   its vertex normals negated.
3. **Edge walking with the top-left fill rule.**  A pixel belongs to a triangle when its centre
   lies inside, or on a left or a top edge: per scan line the pixel centres with
   ``y_top <= yc < y_bottom`` and ``x_left <= xc < x_right``.  Edge crossings are computed from
   the edge's endpoints in a fixed (top-to-bottom) order, so two triangles sharing an edge get
   bit-identical crossings and every pixel along it is covered exactly once.  Spans are clipped
   to the image.
4. **Span set-up** (what the hardware needs per line).  Along an edge the vertex normals are
   interpolated *spherically* (slerp), then again between the two edge crossings; the span-end
   values are those at the first and the last pixel centre.  All other attributes (world position,
   linearly interpolated normal for classic Phong, Gouraud colour, vertex specular, 1/depth) are
   interpolated linearly in the same way.  Interpolation is affine in screen space, like the
   hardware (no perspective correction; the thesis lists it outside these units); every method
   shares it, so the comparison isolates the shading.  H at a span end is computed from the light
   and the viewer at that end's interpolated world position (constant for a directional light
   and a viewer at infinity).
5. **Depth test.**  A z-buffer on 1/z_cam (linear in screen space).  Objects in scene order,
   triangles in mesh order; a fragment wins when it is strictly nearer, so ties keep the first.
   The test runs as a pre-pass over the span geometry; ``shade`` then sends only the spans with
   at least one visible pixel through the shader (``skip_hidden_spans=True``, the default; the
   units process whole spans, so a partly hidden span is shaded in full) and writes the pixels
   that won the depth test.

Intensities are in 8-bit levels (0..255 floats), see ``model.scene`` for the lighting model.

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

from model.render.scene import Material, Scene, SceneObject

NEAR = 1e-3
"""Camera depth below which a vertex counts as behind the eye (its triangle is dropped)."""
MAX_SCREEN_COORD = 2.0**40
"""Largest |x|, |y| in pixels of a drawn triangle's projected corner.  The edge walk is float64:
an edge crossing is found to about |corner| * 2**-51 pixels (2**-11 here), and beyond 2**63 the
pixel indices overflow (a 1e18-unit triangle drew 0 pixels).  A triangle beyond it is refused
with a ``ValueError`` naming it (it is not clipped: clipping would split it into polygons and
break the per-edge slerp of the span set-up)."""

LIGHT_DIRECTIONAL, LIGHT_POINT = 0, 1


# ------------------------------------------------------------------------------------------------
# vector kernels (numba; also usable un-jitted)


@njit(cache=True)
def _norm3(x: float, y: float, z: float) -> tuple[float, float, float]:
    length = np.sqrt(x * x + y * y + z * z)
    if length < 1e-300:
        return 0.0, 0.0, 0.0
    return x / length, y / length, z / length


@njit(cache=True)
def _slerp3(
    ax: float, ay: float, az: float, bx: float, by: float, bz: float, t: float
) -> tuple[float, float, float]:
    """Spherical interpolation of unit vectors a -> b at t in [0, 1] (constant angular speed).

    t = 0 and t = 1 return a and b exactly.  Nearly identical vectors (angle < 1e-9) are lerped
    and normalised.  Antipodal vectors (angle within 1e-9 of pi, the great circle undefined) turn
    about a fixed axis: a x e, e the coordinate axis least aligned with a.
    """
    if t == 0.0:
        return ax, ay, az
    if t == 1.0:
        return bx, by, bz
    cx = ay * bz - az * by
    cy = az * bx - ax * bz
    cz = ax * by - ay * bx
    sin_w = np.sqrt(cx * cx + cy * cy + cz * cz)
    cos_w = ax * bx + ay * by + az * bz
    w = np.arctan2(sin_w, cos_w)
    if w < 1e-9:
        return _norm3(ax + t * (bx - ax), ay + t * (by - ay), az + t * (bz - az))
    if np.pi - w < 1e-9:
        # Antipodal: rotate a by t*pi about an axis perpendicular to a.
        aax, aay, aaz = abs(ax), abs(ay), abs(az)
        if aax <= aay and aax <= aaz:
            px, py, pz = 0.0, az, -ay  # a x (1,0,0)
        elif aay <= aaz:
            px, py, pz = -az, 0.0, ax  # a x (0,1,0)
        else:
            px, py, pz = ay, -ax, 0.0  # a x (0,0,1)
        px, py, pz = _norm3(px, py, pz)
        c = np.cos(np.pi * t)
        s = np.sin(np.pi * t)
        return _norm3(c * ax + s * px, c * ay + s * py, c * az + s * pz)
    s = np.sin(w)
    fa = np.sin((1.0 - t) * w) / s
    fb = np.sin(t * w) / s
    return _norm3(fa * ax + fb * bx, fa * ay + fb * by, fa * az + fb * bz)


@njit(cache=True)
def _slerp_rows(a: np.ndarray, b: np.ndarray, t: np.ndarray, out: np.ndarray) -> None:
    for i in range(t.size):
        out[i, 0], out[i, 1], out[i, 2] = _slerp3(
            a[i, 0], a[i, 1], a[i, 2], b[i, 0], b[i, 1], b[i, 2], t[i]
        )


def slerp(a, b, t) -> np.ndarray:
    """Spherical interpolation of unit 3-vectors, broadcasting ``a`` (..., 3), ``b`` (..., 3) and
    ``t`` (...).  The same kernel the rasteriser and the reference shaders use."""
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    t = np.asarray(t, dtype=np.float64)
    shape = np.broadcast_shapes(a.shape[:-1], b.shape[:-1], t.shape)
    aa = np.ascontiguousarray(np.broadcast_to(a, (*shape, 3)).reshape(-1, 3))
    bb = np.ascontiguousarray(np.broadcast_to(b, (*shape, 3)).reshape(-1, 3))
    tt = np.ascontiguousarray(np.broadcast_to(t, shape).reshape(-1))
    out = np.empty((tt.size, 3))
    _slerp_rows(aa, bb, tt, out)
    return out.reshape((*shape, 3))


@njit(cache=True)
def _light_view(
    px: float,
    py: float,
    pz: float,
    light_kind: int,
    lvec: np.ndarray,
    viewer_local: int,
    vvec: np.ndarray,
) -> tuple[float, float, float, float, float, float]:
    """(L, V) at world point P.  ``lvec``: L (directional) or the light position (point);
    ``vvec``: V (viewer at infinity) or the eye (local viewer)."""
    if light_kind == LIGHT_DIRECTIONAL:
        lx, ly, lz = lvec[0], lvec[1], lvec[2]
    else:
        lx, ly, lz = _norm3(lvec[0] - px, lvec[1] - py, lvec[2] - pz)
    if viewer_local == 0:
        vx, vy, vz = vvec[0], vvec[1], vvec[2]
    else:
        vx, vy, vz = _norm3(vvec[0] - px, vvec[1] - py, vvec[2] - pz)
    return lx, ly, lz, vx, vy, vz


@njit(cache=True)
def _half(
    lx: float, ly: float, lz: float, vx: float, vy: float, vz: float
) -> tuple[float, float, float]:
    """H = (L + V) / |L + V|; when L = -V (undefined) H = V."""
    hx, hy, hz = _norm3(lx + vx, ly + vy, lz + vz)
    if hx == 0.0 and hy == 0.0 and hz == 0.0:
        return vx, vy, vz
    return hx, hy, hz


# ------------------------------------------------------------------------------------------------
# lighting set-up shared by the rasteriser and the shaders


@dataclass(frozen=True, eq=False)
class LightingParams:
    """The light and viewer as the kernels take them."""

    light_kind: int  # LIGHT_DIRECTIONAL | LIGHT_POINT
    lvec: np.ndarray  # L (directional) or light position (point)
    viewer_local: int  # 0: viewer at infinity, 1: local viewer
    vvec: np.ndarray  # V (infinite) or the eye position (local)
    intensity: float  # I_l

    @staticmethod
    def of(scene: Scene) -> LightingParams:
        light = scene.light
        cam = scene.camera
        if light.kind == "directional":
            kind, lvec = LIGHT_DIRECTIONAL, np.array(light.direction)
        else:
            kind, lvec = LIGHT_POINT, np.array(light.position)
        if scene.viewer == "infinite":
            local = 0
            v = np.subtract(cam.eye, cam.target)
            vvec = v / np.linalg.norm(v)
        else:
            local, vvec = 1, np.array(cam.eye, dtype=np.float64)
        return LightingParams(kind, lvec.astype(np.float64), local, vvec, float(light.intensity))

    @property
    def constant_half_vector(self) -> bool:
        """True when H is the same everywhere (directional light, viewer at infinity)."""
        return self.light_kind == LIGHT_DIRECTIONAL and self.viewer_local == 0


@njit(cache=True)
def _vectors_kernel(p: np.ndarray, kind: int, lvec, local: int, vvec, out: np.ndarray) -> None:
    for i in range(p.shape[0]):
        lx, ly, lz, vx, vy, vz = _light_view(p[i, 0], p[i, 1], p[i, 2], kind, lvec, local, vvec)
        hx, hy, hz = _half(lx, ly, lz, vx, vy, vz)
        out[i, 0], out[i, 1], out[i, 2] = lx, ly, lz
        out[i, 3], out[i, 4], out[i, 5] = vx, vy, vz
        out[i, 6], out[i, 7], out[i, 8] = hx, hy, hz


def lighting_vectors(
    points: np.ndarray, params: LightingParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(L, V, H) unit vectors at world points (..., 3)."""
    pts = np.asarray(points, dtype=np.float64)
    flat = np.ascontiguousarray(pts.reshape(-1, 3))
    out = np.empty((flat.shape[0], 9))
    _vectors_kernel(flat, params.light_kind, params.lvec, params.viewer_local, params.vvec, out)
    out = out.reshape((*pts.shape[:-1], 9))
    return out[..., 0:3], out[..., 3:6], out[..., 6:9]


def vertex_lighting(
    normals: np.ndarray, points: np.ndarray, material: Material, params: LightingParams
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per vertex: the Gouraud ambient + diffuse colour (..., 3) in 8-bit levels, the specular
    term (...) in levels, and H (..., 3)."""
    lv, _, hv = lighting_vectors(points, params)
    ndl = np.maximum(0.0, np.einsum("...k,...k->...", normals, lv))
    ndh = np.maximum(0.0, np.einsum("...k,...k->...", normals, hv))
    col = np.asarray(material.colour)
    gour = 255.0 * col * (material.ambient + material.k_d * params.intensity * ndl)[..., None]
    spec = 255.0 * material.k_s * params.intensity * ndh**material.n
    return gour, spec, hv


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


_SPAN_ARRAYS = (
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
        kw = {name: getattr(self, name)[i] for name in _SPAN_ARRAYS}
        for name in ("y", "x_start", "x_end", "tri"):
            kw[name] = int(kw[name])
        for name in ("s_start", "s_end", "z_start", "z_end"):
            kw[name] = float(kw[name])
        return Span(obj=self.obj, **kw)

    def select(self, mask_or_index: np.ndarray) -> Spans:
        """The subset of spans picked by a boolean mask or index array (order kept)."""
        kw = {name: getattr(self, name)[mask_or_index] for name in _SPAN_ARRAYS}
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


# ------------------------------------------------------------------------------------------------
# rasteriser kernels


@njit(cache=True)
def _walk_kernel(
    sx: np.ndarray,  # (T, 3) screen x of the corners
    sy: np.ndarray,  # (T, 3)
    keep: np.ndarray,  # (T,) bool
    width: int,
    height: int,
    out_i: np.ndarray,  # (S_max, 8) int64: tri, y, xs, xe, la, lb, ra, rb
    out_f: np.ndarray,  # (S_max, 4) float: sl, sr, u_start, u_end
) -> int:
    """Edge walking with the top-left rule; returns the number of spans written."""
    n = 0
    for t in range(sx.shape[0]):
        if not keep[t]:
            continue
        # sort the corners by y (stable on the corner index)
        i0, i1, i2 = 0, 1, 2
        if sy[t, i1] < sy[t, i0]:
            i0, i1 = i1, i0
        if sy[t, i2] < sy[t, i1]:
            i1, i2 = i2, i1
            if sy[t, i1] < sy[t, i0]:
                i0, i1 = i1, i0
        y0, y1, y2 = sy[t, i0], sy[t, i1], sy[t, i2]
        if y2 <= y0:
            continue
        row_lo = max(0, int(np.ceil(y0 - 0.5)))
        row_hi = min(height - 1, int(np.ceil(y2 - 0.5)) - 1)
        for row in range(row_lo, row_hi + 1):
            yc = row + 0.5
            # long edge i0 -> i2 (top to bottom)
            s_long = (yc - y0) / (y2 - y0)
            x_long = sx[t, i0] + s_long * (sx[t, i2] - sx[t, i0])
            if yc < y1:
                a, b = i0, i1
            else:
                a, b = i1, i2
            ya, yb = sy[t, a], sy[t, b]
            s_short = (yc - ya) / (yb - ya)
            x_short = sx[t, a] + s_short * (sx[t, b] - sx[t, a])
            if x_long <= x_short:
                xl, xr = x_long, x_short
                la, lb, sl, ra, rb, sr = i0, i2, s_long, a, b, s_short
            else:
                xl, xr = x_short, x_long
                la, lb, sl, ra, rb, sr = a, b, s_short, i0, i2, s_long
            xs = max(0, int(np.ceil(xl - 0.5)))
            xe = min(width - 1, int(np.ceil(xr - 0.5)) - 1)
            if xs > xe:
                continue
            out_i[n, 0] = t
            out_i[n, 1] = row
            out_i[n, 2] = xs
            out_i[n, 3] = xe
            out_i[n, 4] = la
            out_i[n, 5] = lb
            out_i[n, 6] = ra
            out_i[n, 7] = rb
            out_f[n, 0] = sl
            out_f[n, 1] = sr
            out_f[n, 2] = (xs + 0.5 - xl) / (xr - xl)
            out_f[n, 3] = (xe + 0.5 - xl) / (xr - xl)
            n += 1
    return n


def screen_spans(
    screen_xy, width: int, height: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Edge-walk triangles given directly in screen coordinates (the top-left rule, clipped to
    a ``width`` x ``height`` image): ``screen_xy`` (T, 3, 2).  Returns the spans as arrays
    ``(tri, y, x_start, x_end)`` in triangle order, rows top to bottom.  The same kernel
    ``rasterise`` uses."""
    xy = np.asarray(screen_xy, dtype=np.float64)
    if xy.ndim != 3 or xy.shape[1:] != (3, 2):
        raise ValueError(f"screen_xy shape = {xy.shape} is not legal: legal shape is (T, 3, 2)")
    _check_screen(xy[:, :, 0], xy[:, :, 1], np.ones(xy.shape[0], dtype=bool), "screen_xy")
    sx = np.ascontiguousarray(xy[:, :, 0])
    sy = np.ascontiguousarray(xy[:, :, 1])
    rows = np.clip(np.ceil(sy.max(axis=1) - 0.5), 0, height) - np.clip(
        np.ceil(sy.min(axis=1) - 0.5), 0, height
    )
    bound = int(np.maximum(rows, 0).sum())
    geo_i = np.empty((bound, 8), dtype=np.int64)
    geo_f = np.empty((bound, 4))
    keep = np.ones(xy.shape[0], dtype=np.bool_)
    n = _walk_kernel(sx, sy, keep, int(width), int(height), geo_i, geo_f)
    return geo_i[:n, 0].copy(), geo_i[:n, 1].copy(), geo_i[:n, 2].copy(), geo_i[:n, 3].copy()


@njit(cache=True)
def _span_end_kernel(
    geo_i: np.ndarray,  # (S, 8)
    geo_f: np.ndarray,  # (S, 4)
    cn: np.ndarray,  # (T, 3, 3) corner unit normals
    lin: np.ndarray,  # (T, 3, K) corner linear attributes: P(3), N(3), G(3), S, 1/z
    light_kind: int,
    lvec: np.ndarray,
    viewer_local: int,
    vvec: np.ndarray,
    out_n: np.ndarray,  # (S, 2, 3)
    out_h: np.ndarray,  # (S, 2, 3)
    out_lin: np.ndarray,  # (S, 2, K)
) -> None:
    k_lin = lin.shape[2]
    for s in range(geo_i.shape[0]):
        t = geo_i[s, 0]
        la, lb, ra, rb = geo_i[s, 4], geo_i[s, 5], geo_i[s, 6], geo_i[s, 7]
        sl, sr = geo_f[s, 0], geo_f[s, 1]
        # normals at the two edge crossings (slerp along the edges)
        lx, ly, lz = _slerp3(
            cn[t, la, 0], cn[t, la, 1], cn[t, la, 2], cn[t, lb, 0], cn[t, lb, 1], cn[t, lb, 2], sl
        )
        rx, ry, rz = _slerp3(
            cn[t, ra, 0], cn[t, ra, 1], cn[t, ra, 2], cn[t, rb, 0], cn[t, rb, 1], cn[t, rb, 2], sr
        )
        for e in range(2):
            u = geo_f[s, 2 + e]
            nx, ny, nz = _slerp3(lx, ly, lz, rx, ry, rz, u)
            out_n[s, e, 0], out_n[s, e, 1], out_n[s, e, 2] = nx, ny, nz
            for k in range(k_lin):
                left = lin[t, la, k] + sl * (lin[t, lb, k] - lin[t, la, k])
                right = lin[t, ra, k] + sr * (lin[t, rb, k] - lin[t, ra, k])
                out_lin[s, e, k] = left + u * (right - left)
            lx_, ly_, lz_, vx, vy, vz = _light_view(
                out_lin[s, e, 0],
                out_lin[s, e, 1],
                out_lin[s, e, 2],
                light_kind,
                lvec,
                viewer_local,
                vvec,
            )
            hx, hy, hz = _half(lx_, ly_, lz_, vx, vy, vz)
            out_h[s, e, 0], out_h[s, e, 1], out_h[s, e, 2] = hx, hy, hz


@njit(cache=True)
def _depth_kernel(
    y: np.ndarray,
    xs: np.ndarray,
    xe: np.ndarray,
    iw0: np.ndarray,
    iw1: np.ndarray,
    gid: np.ndarray,  # global triangle id per span
    zbuf: np.ndarray,  # (H, W) 1/z, 0 = empty
    idbuf: np.ndarray,  # (H, W) global triangle id, -1 = empty
) -> None:
    for s in range(y.size):
        length = xe[s] - xs[s]
        for k in range(length + 1):
            t = k / length if length > 0 else 0.0
            iw = iw0[s] + t * (iw1[s] - iw0[s])
            x = xs[s] + k
            if iw > zbuf[y[s], x]:
                zbuf[y[s], x] = iw
                idbuf[y[s], x] = gid[s]


# ------------------------------------------------------------------------------------------------
# rasterise


@dataclass(frozen=True, eq=False)
class ObjectRaster:
    """The rasteriser's output for one object."""

    spans: Spans  # every span of the drawn triangles (hidden ones included)
    visible: np.ndarray  # (n_pixels,) bool: the pixel won the depth test
    visible_per_span: np.ndarray  # (S,) int64
    triangles: int
    triangles_culled: int  # back faces
    triangles_clipped: int  # a vertex behind the near plane
    triangle_offset: int  # global triangle id = offset + tri


@dataclass(frozen=True, eq=False)
class Raster:
    """``rasterise`` output: per-object spans and the depth-test winners.  Shade it with any
    number of shaders (``shade``) without rasterising again."""

    scene: Scene
    objects: tuple[ObjectRaster, ...]
    winner: np.ndarray  # (H, W) global triangle id that won the depth test, -1 = background
    depth: np.ndarray  # (H, W) camera depth of the winner, inf = background
    cull_backfaces: bool
    seconds: float


def _project(scene: Scene, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    cam = scene.camera
    r, u, f = cam.basis()
    d = points - np.asarray(cam.eye)
    xc, yc, zc = d @ r, d @ u, d @ f
    focal = (cam.height / 2) / np.tan(np.radians(cam.fov_y) / 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        sx = cam.width / 2 + focal * xc / zc
        sy = cam.height / 2 - focal * yc / zc
    return sx, sy, zc


def _check_screen(sx, sy, keep, what: str, tri=None, vertices=None) -> None:
    """Refuse a drawn triangle with a corner beyond ``MAX_SCREEN_COORD`` (or not finite)."""
    with np.errstate(invalid="ignore"):
        bad = keep[:, None] & ~((np.abs(sx) <= MAX_SCREEN_COORD) & (np.abs(sy) <= MAX_SCREEN_COORD))
    if not bad.any():
        return
    t, c = (int(i) for i in np.argwhere(bad)[0])
    corner = f"({float(sx[t, c]):.3g}, {float(sy[t, c]):.3g})"
    hint = ""
    if tri is None:
        where = f"{what}[{t}, {c}] = {corner}"
    else:
        hint = " (scale the mesh down or move the camera away)"
        v = int(tri[t, c])
        world = ", ".join(f"{x:.3g}" for x in vertices[v])
        where = f"{what}, triangle {t}, vertex {v} = ({world}) projects to {corner} and"
    raise ValueError(
        f"{where} is out of range: legal screen coordinates are |x|, |y| <= 2**40 "
        f"= {MAX_SCREEN_COORD:.3g} pixels{hint}"
    )


def _rasterise_object(
    scene: Scene, index: int, obj: SceneObject, params: LightingParams, cull: bool, offset: int
) -> tuple[ObjectRaster, np.ndarray]:
    mesh = obj.mesh
    cam = scene.camera
    tri = mesh.triangles
    sx_v, sy_v, zc_v = _project(scene, mesh.vertices)
    p = mesh.vertices[tri]  # (T, 3, 3)
    clipped = np.any(zc_v[tri] <= NEAR, axis=1)
    face_n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    facing = np.einsum("tk,tk->t", face_n, np.asarray(cam.eye) - p[:, 0]) > 0
    culled = ~facing & ~clipped if cull else np.zeros_like(facing)
    keep = ~clipped & ~culled
    sx = np.where(keep[:, None], sx_v[tri], 0.0)
    sy = np.where(keep[:, None], sy_v[tri], 0.0)
    _check_screen(sx, sy, keep, f"object {index} ({mesh.name!r})", tri, mesh.vertices)
    # Corner attributes; back faces drawn two-sided get their normals negated.
    sign = np.where(facing, 1.0, -1.0)[:, None, None]
    cn = np.ascontiguousarray(mesh.normals[tri] * sign)
    gour, spec, _ = vertex_lighting(cn, p, obj.material, params)
    with np.errstate(divide="ignore"):
        inv_w = np.where(keep[:, None], 1.0 / zc_v[tri], 0.0)
    lin = np.ascontiguousarray(
        np.concatenate([p, cn, gour, spec[..., None], inv_w[..., None]], axis=2)
    )
    # upper bound of the span count: rows per kept triangle
    ymin = np.where(keep, sy.min(axis=1), 0.0)
    ymax = np.where(keep, sy.max(axis=1), 0.0)
    rows = np.clip(np.ceil(ymax - 0.5), 0, cam.height) - np.clip(np.ceil(ymin - 0.5), 0, cam.height)
    bound = int(np.maximum(rows, 0).sum())
    geo_i = np.empty((bound, 8), dtype=np.int64)
    geo_f = np.empty((bound, 4))
    count = _walk_kernel(sx, sy, keep, cam.width, cam.height, geo_i, geo_f)
    geo_i, geo_f = geo_i[:count], geo_f[:count]
    out_n = np.empty((count, 2, 3))
    out_h = np.empty((count, 2, 3))
    out_lin = np.empty((count, 2, lin.shape[2]))
    _span_end_kernel(
        geo_i,
        geo_f,
        cn,
        lin,
        params.light_kind,
        params.lvec,
        params.viewer_local,
        params.vvec,
        out_n,
        out_h,
        out_lin,
    )
    with np.errstate(divide="ignore"):
        z = 1.0 / out_lin[:, :, 10]
    spans = Spans(
        obj=index,
        y=geo_i[:, 1].copy(),
        x_start=geo_i[:, 2].copy(),
        x_end=geo_i[:, 3].copy(),
        tri=geo_i[:, 0].copy(),
        n_start=out_n[:, 0].copy(),
        n_end=out_n[:, 1].copy(),
        h_start=out_h[:, 0].copy(),
        h_end=out_h[:, 1].copy(),
        nlin_start=out_lin[:, 0, 3:6].copy(),
        nlin_end=out_lin[:, 1, 3:6].copy(),
        p_start=out_lin[:, 0, 0:3].copy(),
        p_end=out_lin[:, 1, 0:3].copy(),
        g_start=out_lin[:, 0, 6:9].copy(),
        g_end=out_lin[:, 1, 6:9].copy(),
        s_start=out_lin[:, 0, 9].copy(),
        s_end=out_lin[:, 1, 9].copy(),
        z_start=z[:, 0].copy(),
        z_end=z[:, 1].copy(),
    )
    inv_w_ends = np.ascontiguousarray(out_lin[:, :, 10])
    orast = ObjectRaster(
        spans=spans,
        visible=np.zeros(0, dtype=bool),  # filled in after the depth pass
        visible_per_span=np.zeros(0, dtype=np.int64),
        triangles=mesh.n_triangles,
        triangles_culled=int(culled.sum()),
        triangles_clipped=int(clipped.sum()),
        triangle_offset=offset,
    )
    return orast, inv_w_ends


def rasterise(scene: Scene, *, cull_backfaces: bool = True) -> Raster:
    """Project, cull, edge-walk and depth-test every object of ``scene``; see the module doc."""
    t0 = time.perf_counter()
    params = LightingParams.of(scene)
    cam = scene.camera
    zbuf = np.zeros((cam.height, cam.width))
    winner = np.full((cam.height, cam.width), -1, dtype=np.int64)
    partial = []
    offset = 0
    for index, obj in enumerate(scene.objects):
        orast, iw = _rasterise_object(scene, index, obj, params, cull_backfaces, offset)
        sp = orast.spans
        iw0, iw1 = iw[:, 0].copy(), iw[:, 1].copy()
        _depth_kernel(sp.y, sp.x_start, sp.x_end, iw0, iw1, sp.tri + offset, zbuf, winner)
        partial.append(orast)
        offset += obj.mesh.n_triangles
    objects = []
    for orast in partial:
        sp = orast.spans
        xs, ys = sp.pixel_xy()
        gid = np.repeat(sp.tri + orast.triangle_offset, sp.lengths)
        visible = winner[ys, xs] == gid
        per_span = (
            np.add.reduceat(visible.astype(np.int64), sp.offsets[:-1])
            if len(sp)
            else (np.zeros(0, dtype=np.int64))
        )
        objects.append(
            ObjectRaster(
                spans=sp,
                visible=visible,
                visible_per_span=per_span,
                triangles=orast.triangles,
                triangles_culled=orast.triangles_culled,
                triangles_clipped=orast.triangles_clipped,
                triangle_offset=orast.triangle_offset,
            )
        )
    with np.errstate(divide="ignore"):
        depth = np.where(winner >= 0, 1.0 / np.maximum(zbuf, 1e-300), np.inf)
    return Raster(scene, tuple(objects), winner, depth, cull_backfaces, time.perf_counter() - t0)


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


def shade(
    raster: Raster, shader: Shader, *, skip_hidden_spans: bool = True, progress: bool = False
) -> Frame:
    """Run ``shader`` over the spans of every object and assemble the frame (depth-tested)."""
    t0 = time.perf_counter()
    scene = raster.scene
    cam = scene.camera
    params = LightingParams.of(scene)
    rgb = np.empty((cam.height, cam.width, 3), dtype=np.uint8)
    rgb[:] = np.asarray(scene.background, dtype=np.uint8)
    obj_id = np.full((cam.height, cam.width), -1, dtype=np.int64)
    tri_id = np.full((cam.height, cam.width), -1, dtype=np.int64)
    specular = None
    counters: dict[str, float] = {}
    spans_shaded = pixels_shaded = longest = 0
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
        xs, ys = sub.pixel_xy()
        xs, ys = xs[vis], ys[vis]
        rgb[ys, xs] = res.rgb[vis]
        obj_id[ys, xs] = sp.obj
        tri_id[ys, xs] = np.repeat(sub.tri, sub.lengths)[vis]
        if res.specular is not None:
            if specular is None:
                specular = np.zeros((cam.height, cam.width))
            specular[ys, xs] = np.asarray(res.specular, dtype=np.float64)[vis]
        for k, v in res.counters.items():
            counters[k] = counters.get(k, 0) + v
        spans_shaded += len(sub)
        pixels_shaded += sub.n_pixels
        longest = max(longest, int(sub.lengths.max()))
        triangles_shaded += int(np.unique(sub.tri).size)
        n_values.add(material.n)
    stats = RenderStats(
        triangles=sum(o.triangles for o in raster.objects),
        triangles_culled=sum(o.triangles_culled for o in raster.objects),
        triangles_clipped=sum(o.triangles_clipped for o in raster.objects),
        triangles_shaded=triangles_shaded,
        spans=sum(len(o.spans) for o in raster.objects),
        spans_shaded=spans_shaded,
        pixels_shaded=pixels_shaded,
        pixels_covered=int((obj_id >= 0).sum()),
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
