# SPDX-License-Identifier: Apache-2.0
"""The per-triangle highlight test of method (g) as one numba kernel per object: the same
decisions as ``reference.object_highlight_flags`` (numpy), bit for bit, at a fraction of its
cost.

``object_highlight_flags`` (the triangles of an object, or some of them) and
``span_highlight_flags`` (one flag per span: each drawn triangle tested once, in the order the
spans first draw it, without sorting the spans) return exactly what
``reference.object_highlight_flags`` returns; ``tests/test_reference.py`` checks it on every
built-in scene and on random and constructed normals.

Most triangles are decided early: one with a corner normal past the threshold (numpy's
maximum can only be larger) is flagged; one whose normals lie in a cap (around their mean,
through the farthest corner) that stays farther from H than the threshold angle, by a margin of
1e-6, is not.  H itself is made in the kernel at the drawn vertices with ``vectors``'
``light_view`` and ``half``, the arithmetic of ``vectors.lighting_vectors``.

How the decisions stay the numpy version's.  The kernel evaluates, per remaining triangle, the
numpy code's own float operations in the numpy code's order (its dot products ``einsum("tk,tk->t")``
add the products as ``(x0 y0 + x2 y2) + x1 y1``, its norms as ``sqrt((x0^2 + x1^2) + x2^2)``,
its cross products term by term): the maximum of N.H over the triangle's edge arcs and, for a
point light or a local viewer, the dot products of the vertex H's with their mean are the same
numbers.  The host then takes ``arccos`` and compares with the threshold angle with numpy's own
calls, so the transcendental functions are numpy's too.  The one step done differently is
numpy's inside test (``np.linalg.det`` and ``np.linalg.solve``, LAPACK): the kernel uses the
triple products (Cramer's rule) and marks a triangle *unsure* when its determinant is within
1e-14 of the 1e-12 cut or a weight is within its rounding bound of 0; an unsure triangle whose
edge maximum already passes the test is flagged (both answers of the inside test then flag
it), and any other unsure triangle is decided by the numpy version itself (none of the
built-in scenes' triangles is).  May import numpy, numba and ``model.render`` ``scene``,
``vectors`` and ``reference``.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numba import njit

from model.render.reference import highlight_threshold
from model.render.reference import object_highlight_flags as numpy_object_highlight_flags
from model.render.reference import triangle_may_show_highlight as reference_triangle_test
from model.render.scene import Scene
from model.render.vectors import LightingParams, half, light_view

DET_CUT = 1e-12  # numpy's |det| > 1e-12: the normals span a cone
DET_BAND = 1e-14  # |det| this close to the cut: LAPACK and the triple product may disagree
W_BOUND = 1e-12  # a weight within W_BOUND (1 + max |w|) / |det| of 0 may change sign
FAR_MARGIN = 1e-6  # radians and cosines to spare when a triangle is skipped as far from H
UNSURE, FAR, NEAR = 1, 2, 3  # the kernel's states besides 0 (decided by max N.H)
_ONES = np.ones(3)  # read-only placeholders of the kernel's unused array arguments
_ONES.flags.writeable = False
_ZEROS = np.zeros((1, 3))
_ZEROS.flags.writeable = False


@njit(cache=True)
def _dot(a0: float, a1: float, a2: float, b0: float, b1: float, b2: float) -> float:
    """numpy's ``einsum("tk,tk->t")`` of one row: ``(a0 b0 + a2 b2) + a1 b1``."""
    return (a0 * b0 + a2 * b2) + a1 * b1


@njit(cache=True)
def _norm(a0: float, a1: float, a2: float) -> float:
    """numpy's ``linalg.norm(axis=-1)`` of one row: ``sqrt((a0^2 + a1^2) + a2^2)``."""
    return math.sqrt((a0 * a0 + a1 * a1) + a2 * a2)


@njit(cache=True)
def _unit_row(a: np.ndarray, v: int, out: np.ndarray) -> None:
    """``out[v] = a[v] / |a[v]|`` (numpy's ``a / linalg.norm(a, axis=-1, keepdims=True)``)."""
    r = _norm(a[v, 0], a[v, 1], a[v, 2])
    out[v, 0], out[v, 1], out[v, 2] = a[v, 0] / r, a[v, 1] / r, a[v, 2] / r


@njit(cache=True)
def _arc_max(
    a0: float, a1: float, a2: float, b0: float, b1: float, b2: float, h0: float, h1: float,
    h2: float,
) -> float:  # fmt: skip
    """``reference``'s max of N.h over the shorter great-circle arc from a to b, one row."""
    best = max(_dot(a0, a1, a2, h0, h1, h2), _dot(b0, b1, b2, h0, h1, h2))
    c0 = a1 * b2 - a2 * b1
    c1 = a2 * b0 - a0 * b2
    c2 = a0 * b1 - a1 * b0
    pn = _norm(c0, c1, c2)
    if not pn > 1e-12:
        return best
    m0, m1, m2 = c0 / pn, c1 / pn, c2 / pn
    d = _dot(h0, h1, h2, m0, m1, m2)
    p0, p1, p2 = h0 - d * m0, h1 - d * m1, h2 - d * m2
    pl = _norm(p0, p1, p2)
    if not pl > 1e-12:
        return best
    q0, q1, q2 = p0 / pl, p1 / pl, p2 / pl
    s = _dot(a1 * q2 - a2 * q1, a2 * q0 - a0 * q2, a0 * q1 - a1 * q0, m0, m1, m2)
    t = _dot(q1 * b2 - q2 * b1, q2 * b0 - q0 * b2, q0 * b1 - q1 * b0, m0, m1, m2)
    if s >= -1e-12 and t >= -1e-12:
        return max(best, pl)
    return best


@njit(cache=True)
def _triangle(nn: np.ndarray, h0: float, h1: float, h2: float) -> tuple[float, bool]:
    """(max of N.h over the spherical triangle of the unit rows ``nn`` (3, 3), unsure): the
    inside test by triple products; ``unsure`` when LAPACK's answer might differ (the value
    returned is then the edge maximum)."""
    a0, a1, a2 = nn[0, 0], nn[0, 1], nn[0, 2]
    b0, b1, b2 = nn[1, 0], nn[1, 1], nn[1, 2]
    c0, c1, c2 = nn[2, 0], nn[2, 1], nn[2, 2]
    e01 = _arc_max(a0, a1, a2, b0, b1, b2, h0, h1, h2)
    e12 = _arc_max(b0, b1, b2, c0, c1, c2, h0, h1, h2)
    best = max(max(e01, e12), _arc_max(c0, c1, c2, a0, a1, a2, h0, h1, h2))
    # columns n0 n1 n2: det = n0 . (n1 x n2); w_i = h . (n_j x n_k) / det (Cramer)
    x0, x1, x2 = b1 * c2 - b2 * c1, b2 * c0 - b0 * c2, b0 * c1 - b1 * c0
    y0, y1, y2 = c1 * a2 - c2 * a1, c2 * a0 - c0 * a2, c0 * a1 - c1 * a0
    z0, z1, z2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
    det = a0 * x0 + a1 * x1 + a2 * x2
    ad = abs(det)
    if abs(ad - DET_CUT) <= DET_BAND:
        return best, True
    if not ad > DET_CUT:
        return best, False
    w0 = (h0 * x0 + h1 * x1 + h2 * x2) / det
    w1 = (h0 * y0 + h1 * y1 + h2 * y2) / det
    w2 = (h0 * z0 + h1 * z1 + h2 * z2) / det
    tol = W_BOUND * (1.0 + max(abs(w0), max(abs(w1), abs(w2)))) / ad
    if w0 < -tol or w1 < -tol or w2 < -tol:
        return best, False
    if w0 > tol and w1 > tol and w2 > tol:
        return 1.0, False
    return best, True


@njit(cache=True)
def _far(
    nn: np.ndarray, h0: float, h1: float, h2: float, cos_lim: float, sin_lim: float, delta: float
) -> bool:
    """True when every normal of the triangle is farther than lim + ``delta`` (< 90 degrees)
    from h by a margin: the cap around the normalised mean normal c through the farthest
    corner (radius r < 90 degrees) holds the geodesic triangle, so angle(N, h) >= angle(c, h)
    - r > lim + delta.  ``cos_lim``, ``sin_lim``: of lim; no sine or cosine per triangle."""
    s0 = (nn[0, 0] + nn[1, 0]) + nn[2, 0]
    s1 = (nn[0, 1] + nn[1, 1]) + nn[2, 1]
    s2 = (nn[0, 2] + nn[1, 2]) + nn[2, 2]
    r = _norm(s0, s1, s2)
    if not r > 1e-6:
        return False
    s0, s1, s2 = s0 / r, s1 / r, s2 / r
    cos_r = 1.0
    for k in range(3):
        cos_r = min(cos_r, _dot(s0, s1, s2, nn[k, 0], nn[k, 1], nn[k, 2]))
    cos_r -= 1e-12
    if not cos_r > 1e-6:  # r at 90 degrees or more: the cap is not convex
        return False
    sin_r = math.sqrt(max(0.0, 1.0 - cos_r * cos_r)) + 1e-12
    # x = r + lim < 180 degrees: cos(x + delta) >= cos x - delta sin x - max(cos x, 0) delta^2/2
    cos_x = cos_r * cos_lim - sin_r * sin_lim
    sin_x = sin_r * cos_lim + cos_r * sin_lim
    bound = cos_x - delta * sin_x - max(cos_x, 0.0) * 0.5 * delta * delta
    return _dot(s0, s1, s2, h0, h1, h2) < bound - FAR_MARGIN


@njit(cache=True)
def _drawn_kernel(
    span_tri: np.ndarray,
    triangles: np.ndarray,
    normals: np.ndarray,
    vertices: np.ndarray,
    eye: np.ndarray,
    cull: bool,
    h_const: np.ndarray,
    h_vertex: np.ndarray,
    per_vertex: bool,
    lit: bool,
    light_kind: int,
    lvec: np.ndarray,
    viewer_local: int,
    vvec: np.ndarray,
    g: float,
    cos_g: float,
    drawn: np.ndarray,
    best: np.ndarray,
    state: np.ndarray,
    dots: np.ndarray,
) -> int:
    """Every triangle ``span_tri`` names, once, in the order of its first span: its index into
    ``drawn``, its maximum of N.H (``best``), its ``state`` (0: decided by ``best``; UNSURE;
    FAR: certainly not flagged; NEAR: certainly flagged; ``best`` is not computed for these
    two) and, with ``per_vertex`` (H per vertex: ``h_vertex``, or with ``lit`` made from the
    light and the viewer at each vertex), the dot products of its vertex H's with their normalised
    mean (``dots``).  ``g``: the threshold angle, ``cos_g`` its cosine (numpy's
    ``threshold ** (1 / n)``).  A constant H with ``lit`` is made from the light and the viewer
    (at vertex 0, as ``vectors.lighting_vectors``).  Returns the count (-1 - s when span s
    names no triangle)."""
    count = 0
    slot = np.full(triangles.shape[0], -1, dtype=np.int64)  # row in ``drawn``, per triangle
    hc = h_const.copy()
    if lit and not per_vertex:
        hc[0], hc[1], hc[2] = half(*light_view(
            vertices[0, 0], vertices[0, 1], vertices[0, 2], light_kind, lvec, viewer_local,
            vvec))  # fmt: skip
    nn = np.empty((3, 3))
    hv = np.empty((3, 3))
    unit_done = np.zeros(normals.shape[0], dtype=np.bool_)
    unit_n = np.empty((normals.shape[0], 3))
    unit_h = np.empty((normals.shape[0] if per_vertex else 0, 3))
    r = _norm(hc[0], hc[1], hc[2])  # numpy: h / |h| (once: H is constant)
    c0, c1, c2 = hc[0] / r, hc[1] / r, hc[2] / r
    # lim + delta: an upper bound of numpy's g + spread + 1e-12 (spread = 0 for a constant H,
    # else 0 or 1.25 x the largest angle + 1e-3: delta = 1.25 x a bound of that angle)
    lim = g + FAR_MARGIN + (1e-3 if per_vertex else 0.0)
    cos_lim, sin_lim = math.cos(lim), math.sin(lim)
    delta = 0.0
    for s in range(span_tri.shape[0]):
        t = span_tri[s]
        if t < 0 or t >= triangles.shape[0]:
            return -1 - s  # the caller raises
        if slot[t] >= 0:
            continue
        slot[t] = count
        drawn[count] = t
        sign = 1.0
        if not cull:
            p = triangles[t, 0]
            d1 = vertices[triangles[t, 1]] - vertices[p]
            d2 = vertices[triangles[t, 2]] - vertices[p]
            f0 = d1[1] * d2[2] - d1[2] * d2[1]
            f1 = d1[2] * d2[0] - d1[0] * d2[2]
            f2 = d1[0] * d2[1] - d1[1] * d2[0]
            e0, e1, e2 = eye[0] - vertices[p, 0], eye[1] - vertices[p, 1], eye[2] - vertices[p, 2]
            sign = 1.0 if _dot(f0, f1, f2, e0, e1, e2) > 0 else -1.0
        for k in range(3):  # numpy: n / |n| per corner (-n / |n| for a flipped back face)
            v = triangles[t, k]
            if not unit_done[v]:
                _unit_row(normals, v, unit_n)
                if lit and per_vertex:  # H at the vertex (lighting_vectors' arithmetic) / |H|
                    x, y, z = half(*light_view(vertices[v, 0], vertices[v, 1], vertices[v, 2],
                                               light_kind, lvec, viewer_local, vvec))  # fmt: skip
                    r = _norm(x, y, z)
                    unit_h[v, 0], unit_h[v, 1], unit_h[v, 2] = x / r, y / r, z / r
                elif per_vertex:
                    _unit_row(h_vertex, v, unit_h)
                unit_done[v] = True
            for j in range(3):
                nn[k, j] = unit_n[v, j] * sign
                if per_vertex:
                    hv[k, j] = unit_h[v, j]
        if per_vertex:
            s0 = (hv[0, 0] + hv[1, 0]) + hv[2, 0]
            s1 = (hv[0, 1] + hv[1, 1]) + hv[2, 1]
            s2 = (hv[0, 2] + hv[1, 2]) + hv[2, 2]
            r = _norm(s0, s1, s2)
            h0, h1, h2 = s0 / r, s1 / r, s2 / r
            lowest = 1.0
            for k in range(3):
                d = _dot(hv[k, 0], hv[k, 1], hv[k, 2], h0, h1, h2)
                dots[count, k] = d
                lowest = min(lowest, d)
            # acos(d) <= pi sqrt((1 - d) / 2): an upper bound of numpy's angle, no acos
            delta = 1.25 * (1.0 + 1e-9) * math.pi * math.sqrt(max(0.0, 0.5 * (1.0 - lowest)))
        else:
            h0, h1, h2 = c0, c1, c2
        state[count] = 0
        corner = max(
            max(_dot(nn[0, 0], nn[0, 1], nn[0, 2], h0, h1, h2),
                _dot(nn[1, 0], nn[1, 1], nn[1, 2], h0, h1, h2)),
            _dot(nn[2, 0], nn[2, 1], nn[2, 2], h0, h1, h2),
        )  # fmt: skip
        if corner > cos_g + FAR_MARGIN:  # a corner passes: numpy's maximum passes too
            state[count] = NEAR
        elif lim + delta < 0.5 * math.pi and _far(nn, h0, h1, h2, cos_lim, sin_lim, delta):
            state[count] = FAR
        else:
            best[count], unsure = _triangle(nn, h0, h1, h2)
            if unsure:
                state[count] = UNSURE
        count += 1
    return count


def _readonly(a: np.ndarray, dtype) -> np.ndarray:
    """A C-contiguous read-only view (no copy of a mesh's frozen arrays): the kernel's inputs
    are always read-only, so that numba compiles it once."""
    if a.dtype == dtype and not a.flags.writeable and a.flags.c_contiguous:
        return a
    view = np.ascontiguousarray(a, dtype=dtype).view()
    view.flags.writeable = False
    return view


@lru_cache(maxsize=256)
def _threshold_angle(thr: float, n: int) -> tuple[float, float]:
    """(g, cos g): numpy's ``thr ** (1 / n)`` and its ``arccos``, as the numpy version makes
    them (array calls)."""
    cos_g = min(thr, 1.0) ** (1.0 / np.full(1, float(n)))
    return float(np.arccos(np.clip(cos_g, -1.0, 1.0))[0]), float(cos_g[0])


def _clip1(x: np.ndarray) -> np.ndarray:
    """``np.clip(x, -1, 1)``, the same values, without its Python wrapper."""
    return np.minimum(np.maximum(x, -1.0), 1.0)


def _light_args(lights: LightingParams | None) -> tuple:
    """The kernel's light and viewer arguments (placeholders without ``lights``)."""
    if lights is None:
        return 0, _ONES, 0, _ONES
    return (
        int(lights.light_kind), _readonly(lights.lvec, np.float64), int(lights.viewer_local),
        _readonly(lights.vvec, np.float64),
    )  # fmt: skip


def _decide(
    span_tri: np.ndarray,
    triangles: np.ndarray,
    normals: np.ndarray,
    n: int,
    thr: float,
    h: np.ndarray,
    per_vertex: bool,
    numpy_flags,
    vertices: np.ndarray | None = None,
    eye: np.ndarray | None = None,
    lights: LightingParams | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(drawn, flags) for the triangles ``span_tri`` names (``_drawn_kernel``), finished with
    numpy's own calls; ``numpy_flags(subset)`` decides the unsure ones that are not flagged.
    ``h``: (3,) constant or (V, 3) per vertex, or with ``lights`` made from the light and the
    viewer (at each drawn vertex of ``vertices`` for ``per_vertex``); ``eye`` given: two-sided
    (back faces flipped)."""
    if not thr > 0:  # numpy refuses it too (levels = 0)
        raise ValueError(f"threshold = {thr!r} is out of range: legal range is > 0")
    span_tri = _readonly(np.asarray(span_tri).reshape(-1), np.int64)
    tri_count = len(triangles)
    size = min(span_tri.size, tri_count)
    drawn = np.empty(size, dtype=np.int64)
    best = np.empty(size)
    state = np.empty(size, dtype=np.int8)
    dots = np.empty((size if per_vertex else 0, 3))
    h = _readonly(h, np.float64)
    g, cos_g = _threshold_angle(float(thr), int(n))  # numpy's own threshold angle
    lit = lights is not None
    count = _drawn_kernel(
        span_tri, _readonly(triangles, np.int64), _readonly(normals, np.float64),
        _ZEROS if vertices is None else _readonly(vertices, np.float64),
        _ONES if eye is None else _readonly(eye, np.float64), eye is None,
        _ONES if per_vertex or lit else h,
        h if per_vertex and not lit else _ZEROS,
        per_vertex, lit, *_light_args(lights), g, cos_g, drawn, best, state, dots,
    )  # fmt: skip
    if count < 0:
        raise ValueError(
            f"triangle index {int(span_tri[-1 - count])} is out of range: legal range is "
            f"0..{tri_count - 1}"
        )
    drawn = drawn[:count]
    if thr > 1.0:  # the specular term can never reach it
        return drawn, np.zeros(count, dtype=bool)
    flags = state[:count] == NEAR
    # numpy's own steps from here, on the triangles the kernel left open: arccos, the compare
    rest = np.flatnonzero(state[:count] < FAR)
    if rest.size:
        spread = 0.0
        if per_vertex:
            ang = np.arccos(_clip1(dots[rest]))
            spread = ang.max(axis=1)
            spread = np.where(spread > 0, spread * 1.25 + 1e-3, 0.0)
        angle = np.arccos(_clip1(best[rest]))
        flags[rest] = angle <= g + spread + 1e-12
        # unsure and not flagged by its edges: LAPACK's inside test decides (numpy's own code)
        ask = rest[(state[rest] == UNSURE) & ~flags[rest]]
        if ask.size:
            flags[ask] = numpy_flags(drawn[ask])
    return drawn, flags


def drawn_highlight_flags(
    scene: Scene,
    span_tri: np.ndarray,
    obj: int = 0,
    levels: float = 0.5,
    cull_backfaces: bool = True,
    params: LightingParams | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(drawn, flags): the triangles of object ``obj`` that ``span_tri`` names, each once in the
    order of its first appearance, and ``reference.object_highlight_flags(..., triangles=drawn)``
    for them (the same bools).  ``params``: the scene's ``LightingParams`` if already made."""
    o = scene.objects[obj]
    mesh = o.mesh
    thr = highlight_threshold(o.material.k_s, scene.light.intensity, levels)
    if not np.isfinite(thr):  # k_s or I_l = 0: no highlight can be seen
        thr = 2.0  # (numpy returns False for every triangle; so does thr > 1)
    params = params or LightingParams.of(scene)
    per_vertex = not params.constant_half_vector
    return _decide(  # H made by the kernel from the light and the viewer
        span_tri, mesh.triangles, mesh.normals, o.material.n, thr, _ONES, per_vertex,
        lambda subset: numpy_object_highlight_flags(
            scene, obj, levels, cull_backfaces, triangles=subset
        ),
        mesh.vertices, None if cull_backfaces else np.asarray(scene.camera.eye), params,
    )  # fmt: skip


def triangle_may_show_highlight(normals, H, n: int, threshold: float) -> np.ndarray:
    """``reference.triangle_may_show_highlight`` (the same bools) by the kernel, for (T, 3, 3)
    unit normals, H (3,) constant or (T, 3, 3) per vertex and one n."""
    nn = np.asarray(normals, dtype=np.float64)
    h = np.asarray(H, dtype=np.float64)
    t_count = nn.shape[0]
    if nn.ndim != 3 or nn.shape[1:] != (3, 3) or h.shape not in ((3,), (t_count, 3, 3)):
        raise ValueError(
            f"normals shape = {nn.shape}, H shape = {h.shape} are not legal: legal are "
            "(T, 3, 3) and (3,) or (T, 3, 3)"
        )
    triangles = np.arange(3 * t_count).reshape(t_count, 3)
    per_vertex = h.ndim == 3
    _, flags = _decide(
        np.arange(t_count), triangles, nn.reshape(-1, 3), int(n), float(threshold),
        h.reshape(-1, 3) if per_vertex else h, per_vertex,
        lambda subset: reference_triangle_test(
            nn[subset], h[subset] if per_vertex else h, n, threshold
        ),
    )  # fmt: skip
    return flags


def object_highlight_flags(
    scene: Scene,
    obj: int = 0,
    levels: float = 0.5,
    cull_backfaces: bool = True,
    triangles: np.ndarray | None = None,
) -> np.ndarray:
    """``reference.object_highlight_flags`` (same arguments, same bools) by the kernel."""
    tri_count = len(scene.objects[obj].mesh.triangles)
    wanted = np.arange(tri_count) if triangles is None else np.asarray(triangles).reshape(-1)
    drawn, flags = drawn_highlight_flags(scene, wanted, obj, levels, cull_backfaces)
    at = np.zeros(tri_count, dtype=bool)
    at[drawn] = flags
    return at[wanted]


def span_highlight_flags(
    scene: Scene,
    span_tri: np.ndarray,
    obj: int = 0,
    levels: float = 0.5,
    params: LightingParams | None = None,
) -> tuple[np.ndarray, int]:
    """(per span: its triangle's flag, the number of drawn triangles flagged): the host tests
    each triangle it draws once (``drawn_highlight_flags``)."""
    tri_count = len(scene.objects[obj].mesh.triangles)
    drawn, flags = drawn_highlight_flags(scene, span_tri, obj, levels, params=params)
    at = np.zeros(tri_count, dtype=bool)
    at[drawn] = flags
    return at[np.asarray(span_tri)], int(np.count_nonzero(flags))
