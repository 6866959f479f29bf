# SPDX-License-Identifier: Apache-2.0
"""The float rasteriser: the "external device" of the patent that feeds the shading units.

Owns projection, back-face culling, the edge walk with the top-left fill rule, the span
set-up and the depth test: ``rasterise`` (a ``Raster`` of per-object ``ObjectRaster``),
``screen_spans`` (the edge walk alone) and their numba kernels.  May import numpy, numba and
``model.render`` ``scene``, ``vectors`` and ``spans``; shading the spans is
``model.render.shade`` (``render(scene, shader)`` = ``shade(rasterise(scene), shader)``).

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

Intensities are in 8-bit levels (0..255 floats), see ``model.render.scene`` for the lighting
model.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from numba import njit

from model.render.scene import Scene, SceneObject
from model.render.spans import Spans
from model.render.vectors import LightingParams, half, light_view, slerp3, vertex_lighting

NEAR = 1e-3
"""Camera depth below which a vertex counts as behind the eye (its triangle is dropped)."""
MAX_SCREEN_COORD = 2.0**40
"""Largest |x|, |y| in pixels of a drawn triangle's projected corner.  The edge walk is float64:
an edge crossing is found to about |corner| * 2**-51 pixels (2**-11 here), and beyond 2**63 the
pixel indices overflow (a 1e18-unit triangle drew 0 pixels).  A triangle beyond it is refused
with a ``ValueError`` naming it (it is not clipped: clipping would split it into polygons and
break the per-edge slerp of the span set-up)."""


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
        lx, ly, lz = slerp3(
            cn[t, la, 0], cn[t, la, 1], cn[t, la, 2], cn[t, lb, 0], cn[t, lb, 1], cn[t, lb, 2], sl
        )
        rx, ry, rz = slerp3(
            cn[t, ra, 0], cn[t, ra, 1], cn[t, ra, 2], cn[t, rb, 0], cn[t, rb, 1], cn[t, rb, 2], sr
        )
        for e in range(2):
            u = geo_f[s, 2 + e]
            nx, ny, nz = slerp3(lx, ly, lz, rx, ry, rz, u)
            out_n[s, e, 0], out_n[s, e, 1], out_n[s, e, 2] = nx, ny, nz
            for k in range(k_lin):
                left = lin[t, la, k] + sl * (lin[t, lb, k] - lin[t, la, k])
                right = lin[t, ra, k] + sr * (lin[t, rb, k] - lin[t, ra, k])
                out_lin[s, e, k] = left + u * (right - left)
            lx_, ly_, lz_, vx, vy, vz = light_view(
                out_lin[s, e, 0],
                out_lin[s, e, 1],
                out_lin[s, e, 2],
                light_kind,
                lvec,
                viewer_local,
                vvec,
            )
            hx, hy, hz = half(lx_, ly_, lz_, vx, vy, vz)
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
