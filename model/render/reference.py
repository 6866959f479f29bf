# SPDX-License-Identifier: Apache-2.0
"""Float span shaders (the accuracy references) and the thesis's per-triangle highlight test.

Owns the float shaders (``exact_blinn``, ``phong``, ``gouraud_float``, ``SHADERS``,
``float_levels``, ``quantise``), the highlight test (``highlight_threshold``,
``max_dot_over_spherical_triangle``, ``triangle_may_show_highlight``,
``object_highlight_flags``) and the diffuse test (``normal_spread_deg``,
``object_diffuse_flags``).  May import numpy, numba and ``model.render`` ``scene``,
``vectors``, ``spans`` and ``shade``.

Shaders (``model.render.shade.Shader``: ``shader(spans, ctx) -> ShadeResult``), all in float64:

* ``exact_blinn`` -- method (a), the accuracy reference: per pixel the normal and the half-vector
  are interpolated *spherically* between the span ends (slerp with t = (x - x_start) /
  (x_end - x_start), t = 0 for a 1-pixel span), L comes from the linearly interpolated world
  position (constant for a directional light), and
  ``I_c = 255 * (colour_c * (ambient + k_d * I_l * max(0, N.L)) + k_s * I_l * max(0, N.H)**n)``.
* ``phong`` -- method (b), classic Phong: the normal and the world position are interpolated
  linearly across the span (from the linearly interpolated edge values), N is normalised, and
  L, V and H are computed per pixel from the position; same lighting.
* ``gouraud_float`` -- method (f) in float: ambient + diffuse *and* the specular term are lit at
  the vertices and interpolated linearly (the specular adds the same value to R, G and B).

Every shader ends with the same 8-bit quantisation, ``quantise``: round half up
(``floor(x + 0.5)``) and saturate to 0..255.  Each also returns its float specular term per
pixel (``ShadeResult.specular``, levels), from which ``metrics.highlight_mask`` is made.

``float_levels(spans, ctx, method)`` gives the unquantised float RGB for any of the three.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from model.render.scene import Scene, check_int, check_range
from model.render.shade import ShadeContext, ShadeResult
from model.render.spans import Spans
from model.render.vectors import (
    LightingParams,
    half,
    light_view,
    lighting_vectors,
    norm3,
    slerp3,
)

METHOD_EXACT, METHOD_PHONG, METHOD_GOURAUD = 0, 1, 2
_METHODS = {"exact_blinn": METHOD_EXACT, "phong": METHOD_PHONG, "gouraud_float": METHOD_GOURAUD}


def quantise(levels: np.ndarray) -> np.ndarray:
    """Float intensities in 8-bit levels -> uint8: round half up, then saturate to 0..255."""
    return np.clip(np.floor(np.asarray(levels, dtype=np.float64) + 0.5), 0, 255).astype(np.uint8)


@njit(cache=True)
def _shade_kernel(
    method: int,
    xs: np.ndarray,
    xe: np.ndarray,
    offsets: np.ndarray,
    n0: np.ndarray,
    n1: np.ndarray,
    h0: np.ndarray,
    h1: np.ndarray,
    nl0: np.ndarray,
    nl1: np.ndarray,
    p0: np.ndarray,
    p1: np.ndarray,
    g0: np.ndarray,
    g1: np.ndarray,
    s0: np.ndarray,
    s1: np.ndarray,
    light_kind: int,
    lvec: np.ndarray,
    viewer_local: int,
    vvec: np.ndarray,
    i_l: float,
    colour: np.ndarray,
    ambient: float,
    k_d: float,
    k_s: float,
    n_exp: int,
    out: np.ndarray,  # (P, 3) float levels
    out_spec: np.ndarray,  # (P,) float levels
) -> None:
    c_spec = 255.0 * k_s * i_l
    for s in range(xs.size):
        length = xe[s] - xs[s]
        base = offsets[s]
        for k in range(length + 1):
            t = k / length if length > 0 else 0.0
            if method == METHOD_GOURAUD:
                spec = s0[s] + t * (s1[s] - s0[s])
                for c in range(3):
                    out[base + k, c] = g0[s, c] + t * (g1[s, c] - g0[s, c]) + spec
                out_spec[base + k] = spec
                continue
            px = p0[s, 0] + t * (p1[s, 0] - p0[s, 0])
            py = p0[s, 1] + t * (p1[s, 1] - p0[s, 1])
            pz = p0[s, 2] + t * (p1[s, 2] - p0[s, 2])
            lx, ly, lz, vx, vy, vz = light_view(px, py, pz, light_kind, lvec, viewer_local, vvec)
            if method == METHOD_EXACT:
                nx, ny, nz = slerp3(n0[s, 0], n0[s, 1], n0[s, 2], n1[s, 0], n1[s, 1], n1[s, 2], t)
                hx, hy, hz = slerp3(h0[s, 0], h0[s, 1], h0[s, 2], h1[s, 0], h1[s, 1], h1[s, 2], t)
            else:
                nx, ny, nz = norm3(
                    nl0[s, 0] + t * (nl1[s, 0] - nl0[s, 0]),
                    nl0[s, 1] + t * (nl1[s, 1] - nl0[s, 1]),
                    nl0[s, 2] + t * (nl1[s, 2] - nl0[s, 2]),
                )
                hx, hy, hz = half(lx, ly, lz, vx, vy, vz)
            ndl = max(0.0, nx * lx + ny * ly + nz * lz)
            ndh = max(0.0, nx * hx + ny * hy + nz * hz)
            spec = c_spec * ndh**n_exp
            diffuse = ambient + k_d * i_l * ndl
            for c in range(3):
                out[base + k, c] = 255.0 * colour[c] * diffuse + spec
            out_spec[base + k] = spec


def float_levels(spans: Spans, ctx: ShadeContext, method: str) -> tuple[np.ndarray, np.ndarray]:
    """Unquantised (n_pixels, 3) RGB and (n_pixels,) specular, in 8-bit levels, of ``method``
    ("exact_blinn" | "phong" | "gouraud_float")."""
    if method not in _METHODS:
        legal = " | ".join(_METHODS)
        raise ValueError(f"method = {method!r} is not legal: legal values are {legal}")
    out = np.empty((spans.n_pixels, 3))
    out_spec = np.empty(spans.n_pixels)
    m = ctx.material
    lp = ctx.lighting
    _shade_kernel(
        _METHODS[method],
        spans.x_start,
        spans.x_end,
        spans.offsets,
        spans.n_start,
        spans.n_end,
        spans.h_start,
        spans.h_end,
        spans.nlin_start,
        spans.nlin_end,
        spans.p_start,
        spans.p_end,
        spans.g_start,
        spans.g_end,
        spans.s_start,
        spans.s_end,
        lp.light_kind,
        lp.lvec,
        lp.viewer_local,
        lp.vvec,
        lp.intensity,
        np.asarray(m.colour, dtype=np.float64),
        m.ambient,
        m.k_d,
        m.k_s,
        m.n,
        out,
        out_spec,
    )
    return out, out_spec


def exact_blinn(spans: Spans, ctx: ShadeContext) -> ShadeResult:
    """Method (a): exact float Blinn with per-pixel spherical interpolation of N and H."""
    rgb, spec = float_levels(spans, ctx, "exact_blinn")
    return ShadeResult(quantise(rgb), spec)


def phong(spans: Spans, ctx: ShadeContext) -> ShadeResult:
    """Method (b): classic float Phong (linear N and position, normalised, H per pixel)."""
    rgb, spec = float_levels(spans, ctx, "phong")
    return ShadeResult(quantise(rgb), spec)


def gouraud_float(spans: Spans, ctx: ShadeContext) -> ShadeResult:
    """Method (f) in float: everything lit at the vertices and interpolated linearly."""
    rgb, spec = float_levels(spans, ctx, "gouraud_float")
    return ShadeResult(quantise(rgb), spec)


SHADERS = {"exact_blinn": exact_blinn, "phong": phong, "gouraud_float": gouraud_float}


# ------------------------------------------------------------------------------------------------
# the highlight test (structure-adaptive shading, the thesis; docs/scenes.md)


def highlight_threshold(k_s: float, intensity: float, levels: float = 0.5) -> float:
    """The smallest value of cos^n(delta) whose specular term ``255 * k_s * I_l * cos^n`` still
    reaches ``levels`` 8-bit levels: ``levels / (255 * k_s * I_l)`` (inf when k_s * I_l = 0: no
    highlight can ever be visible).  Default 0.5 levels: below that a term cannot change a
    correctly rounded pixel by itself."""
    check_range("levels", levels, 0.0, 255.0)
    c = 255.0 * check_range("k_s", k_s, 0.0, 1.0) * check_range("intensity", intensity, 0.0, 16.0)
    return float("inf") if c == 0 else levels / c


def _max_dot_on_arc(a: np.ndarray, b: np.ndarray, h: np.ndarray) -> np.ndarray:
    """max of N.h over the shorter great-circle arc from a to b (unit rows; (T, 3) each)."""
    best = np.maximum(np.einsum("tk,tk->t", a, h), np.einsum("tk,tk->t", b, h))
    plane = np.cross(a, b)
    pn = np.linalg.norm(plane, axis=1)
    ok = pn > 1e-12
    m = np.zeros_like(plane)
    m[ok] = plane[ok] / pn[ok, None]
    # projection of h onto the arc's plane; its direction is the arc point nearest h
    proj = h - np.einsum("tk,tk->t", h, m)[:, None] * m
    pl = np.linalg.norm(proj, axis=1)
    ok &= pl > 1e-12
    q = np.zeros_like(proj)
    q[ok] = proj[ok] / pl[ok, None]
    # q lies on the arc when it is between a and b: (a x q) and (q x b) both along the plane normal
    inside = ok & (np.einsum("tk,tk->t", np.cross(a, q), m) >= -1e-12)
    inside &= np.einsum("tk,tk->t", np.cross(q, b), m) >= -1e-12
    return np.where(inside, np.maximum(best, pl), best)


def max_dot_over_spherical_triangle(normals: np.ndarray, h: np.ndarray) -> np.ndarray:
    """The exact maximum of N.h over the geodesic triangle spanned by three unit normals.

    ``normals`` (T, 3, 3) (triangle, corner, xyz), ``h`` (T, 3) unit.  If h lies inside the
    spherical triangle (h = a N0 + b N1 + c N2 with a, b, c >= 0) the maximum is 1; otherwise it
    is attained on an edge (a linear function restricted to a convex spherical region), and on an
    edge arc it is at an end or at the arc point nearest h.  Triangles whose corners are
    (nearly) coplanar with the origin (degenerate) are handled through the edge maximum.
    """
    nn = np.asarray(normals, dtype=np.float64)
    h = np.asarray(h, dtype=np.float64)
    n0, n1, n2 = nn[:, 0], nn[:, 1], nn[:, 2]
    best = np.maximum.reduce(
        [_max_dot_on_arc(n0, n1, h), _max_dot_on_arc(n1, n2, h), _max_dot_on_arc(n2, n0, h)]
    )
    # inside test: solve [n0 n1 n2] w = h; all weights >= 0 -> h is in the cone
    mats = np.stack([n0, n1, n2], axis=2)  # columns
    det = np.linalg.det(mats)
    ok = np.abs(det) > 1e-12
    w = np.zeros((nn.shape[0], 3))
    if ok.any():
        w[ok] = np.linalg.solve(mats[ok], h[ok][:, :, None])[:, :, 0]
    inside = ok & np.all(w >= 0.0, axis=1)
    return np.where(inside, 1.0, best)


def triangle_may_show_highlight(normals, H, n, threshold) -> np.ndarray:
    """The thesis's per-triangle highlight test, made exact for the normals and conservative
    for H.  Returns a bool per triangle: True = a visible highlight may fall inside.

    ``normals``: (3, 3) or (T, 3, 3) unit vertex normals.  ``H``: the half-vector, (3,) for a
    constant H, (T, 3) per triangle, or (T, 3, 3) / (3, 3) per vertex (point light or local
    viewer).  ``n``: the exponent 1..1000 (scalar or (T,)).  ``threshold``: the smallest visible
    value of cos^n (see ``highlight_threshold``); the highlight boundary is the angle
    ``g = arccos(threshold**(1/n))``.

    The test.  The thesis compares the vertex (edge) dot products N.H with the threshold cos^n(g).
    Testing only the vertices misses a highlight whose epicentre lies inside a triangle or on an
    edge while all three vertices are outside it (large triangles, large n): exactly the
    highlights Gouraud shading loses.  So the test takes the *maximum of N.H over the whole
    spherical triangle* spanned by the vertex normals -- the set of normals the spherical
    interpolation produces (slerp along the edges, then along the spans, stays inside it) -- in
    closed form (``max_dot_over_spherical_triangle``: h inside the cone -> 1, else the best point
    of the three edge arcs), and says "may show" when ``max N.H >= cos g``.

    Varying H (per-vertex H given): H is bounded by the cone around the normalised mean H_c of
    the three vertex H's with half-angle r = the largest angle from H_c to a vertex H, enlarged by
    a margin (x 1.25 + 1e-3 rad).  Then the test is ``angle(N, H_c) <= g + r`` for some N in the
    triangle.  H inside a triangle comes from the interpolated position, not from interpolating
    the vertex H's, so it can leave that cone only by a second-order amount (the triangle's size
    relative to its distance to the light and the eye); the margin covers this for every
    triangle that is small against those distances.  A highlight can be missed only for a huge
    triangle very close to a point light or a local eye, where the H field curves by more than
    25 % of its vertex spread -- not the case in the built-in scenes.  For a constant H (a
    directional light and a viewer at infinity) the test is exact: it never misses a highlight
    and reports "may show" only when some interpolated normal really reaches the threshold.
    """
    nn = np.asarray(normals, dtype=np.float64)
    single = nn.ndim == 2
    if single:
        nn = nn[None]
    if nn.ndim != 3 or nn.shape[1:] != (3, 3):
        raise ValueError(
            f"normals shape = {np.shape(normals)} is not legal: legal is (3, 3) or (T, 3, 3)"
        )
    t_count = nn.shape[0]
    nn = nn / np.linalg.norm(nn, axis=2, keepdims=True)
    h = np.asarray(H, dtype=np.float64)
    if h.shape == (3,):
        h = np.broadcast_to(h, (t_count, 3))
    elif h.shape == (3, 3) and single:
        h = h[None]
    if h.shape not in ((t_count, 3), (t_count, 3, 3)):
        raise ValueError(
            f"H shape = {np.shape(H)} is not legal: legal is (3,), (T, 3) or (T, 3, 3) "
            f"with T = {t_count}"
        )
    n_arr = np.asarray(n)
    if n_arr.dtype.kind not in "iu":
        check_int("n", n if n_arr.ndim == 0 else n_arr.ravel()[0], 1, 1000)
    if n_arr.size:
        check_int("n", int(n_arr.min()), 1, 1000)
        check_int("n", int(n_arr.max()), 1, 1000)
    n_arr = np.broadcast_to(n_arr.astype(np.float64), (t_count,))
    thr = float(threshold)
    if not thr > 0:
        raise ValueError(f"threshold = {threshold!r} is out of range: legal range is > 0")
    if thr > 1.0:  # the specular term can never reach it
        out = np.zeros(t_count, dtype=bool)
        return False if single else out
    cos_g = thr ** (1.0 / n_arr)
    g = np.arccos(np.clip(cos_g, -1.0, 1.0))
    if h.ndim == 2:
        hc = h / np.linalg.norm(h, axis=1, keepdims=True)
        spread = np.zeros(t_count)
    else:
        hv = h / np.linalg.norm(h, axis=2, keepdims=True)
        hc = hv.sum(axis=1)
        hc /= np.linalg.norm(hc, axis=1, keepdims=True)
        ang = np.arccos(np.clip(np.einsum("tvk,tk->tv", hv, hc), -1.0, 1.0))
        spread = ang.max(axis=1)
        spread = np.where(spread > 0, spread * 1.25 + 1e-3, 0.0)
    best = max_dot_over_spherical_triangle(nn, hc)
    angle = np.arccos(np.clip(best, -1.0, 1.0))
    out = angle <= g + spread + 1e-12
    return bool(out[0]) if single else out


def object_highlight_flags(
    scene: Scene,
    obj: int = 0,
    levels: float = 0.5,
    cull_backfaces: bool = True,
    triangles: np.ndarray | None = None,
) -> np.ndarray:
    """``triangle_may_show_highlight`` for every triangle of object ``obj``: (T,) bool.

    With ``triangles`` (indices into the mesh) only those are tested and their flags returned,
    in that order: the host tests just the triangles it draws.

    The vertex H's come from the scene's light and viewer (a constant H for a directional light
    and a viewer at infinity); the threshold is ``highlight_threshold(k_s, I_l, levels)``.  Back
    faces drawn two-sided (``cull_backfaces=False``) use negated normals, like the rasteriser.
    """
    o = scene.objects[obj]
    mesh = o.mesh
    params = LightingParams.of(scene)
    tri = mesh.triangles if triangles is None else mesh.triangles[np.asarray(triangles)]
    nn = mesh.normals[tri]
    if not cull_backfaces:
        p = mesh.vertices[tri]
        fn = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        facing = np.einsum("tk,tk->t", fn, np.asarray(scene.camera.eye) - p[:, 0]) > 0
        nn = nn * np.where(facing, 1.0, -1.0)[:, None, None]
    thr = highlight_threshold(o.material.k_s, scene.light.intensity, levels)
    if not np.isfinite(thr):
        return np.zeros(len(tri), dtype=bool)
    if params.constant_half_vector:
        _, _, h = lighting_vectors(mesh.vertices[:1], params)
        hh = h[0]
    else:
        _, _, hv = lighting_vectors(mesh.vertices, params)
        hh = hv[tri]
    return triangle_may_show_highlight(nn, hh, o.material.n, thr)


# ------------------------------------------------------------------------------------------------
# the diffuse test (the diffuse term through the specular unit on curved triangles only)


def normal_spread_deg(normals: np.ndarray) -> np.ndarray:
    """The largest angle (degrees) between two of a triangle's vertex normals: (T, 3, 3) ->
    (T,).  The normals are normalised here; 0 for a flat-shaded triangle."""
    nn = np.asarray(normals, dtype=np.float64)
    if nn.ndim != 3 or nn.shape[1:] != (3, 3):
        raise ValueError(f"normals shape = {nn.shape} is not legal: legal is (T, 3, 3)")
    nn = nn / np.linalg.norm(nn, axis=2, keepdims=True)
    dots = np.stack(
        [np.einsum("tk,tk->t", nn[:, i], nn[:, j]) for i, j in ((0, 1), (1, 2), (2, 0))], axis=1
    )
    return np.degrees(np.arccos(np.clip(dots.min(axis=1), -1.0, 1.0)))


def object_diffuse_flags(
    scene: Scene, obj: int = 0, spread_deg: float = 10.0, triangles: np.ndarray | None = None
) -> np.ndarray:
    """The host's cheap test for the diffuse term: True for the triangles of object ``obj``
    (or just ``triangles``, in that order) whose vertex normals spread by more than
    ``spread_deg`` degrees (``normal_spread_deg``), where linear interpolation of the
    vertex-lit N.L is least accurate.  Flat triangles keep the Gouraud diffuse term, which is
    then exact for a directional light."""
    check_range("spread_deg", spread_deg, 0.0, 180.0)
    mesh = scene.objects[obj].mesh
    tri = mesh.triangles if triangles is None else mesh.triangles[np.asarray(triangles)]
    return normal_spread_deg(mesh.normals[tri]) > spread_deg
