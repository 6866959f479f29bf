# SPDX-License-Identifier: Apache-2.0
"""Float reference shaders, the 8-bit quantisation and the per-triangle highlight test."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from model.render import highlight, reference, scenefile
from model.render.raster import rasterise
from model.render.reference import (
    highlight_threshold,
    max_dot_over_spherical_triangle,
    quantise,
    triangle_may_show_highlight,
)
from model.render.scene import Camera, Light, Material, Mesh, Scene, SceneObject
from model.render.shade import ShadeContext, render, shade
from model.render.vectors import LightingParams, slerp
from model.study.adaptive import with_shininess


def test_quantise_rounds_half_up_and_saturates() -> None:
    x = np.array([-3.0, -0.5, 0.0, 0.49, 0.5, 1.5, 2.5, 254.49, 254.5, 255.0, 300.0])
    assert quantise(x).tolist() == [0, 0, 0, 0, 1, 2, 3, 254, 255, 255, 255]
    assert quantise(x).dtype == np.uint8


def flat_scene(light: Light, viewer: str, n: int = 40, tilt=(0.2, -0.1, 1.0)) -> Scene:
    """A square with one constant (tilted) normal at every vertex."""
    v = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float64)
    nrm = np.tile(np.asarray(tilt, dtype=np.float64), (4, 1))
    mesh = Mesh(v, [[0, 1, 2], [0, 2, 3]], nrm)
    cam = Camera((0.3, -2.0, 2.5), (0, 0, 0), (0, 0, 1), 50.0, 64, 64)
    mat = Material(ambient=0.1, k_d=0.5, k_s=0.6, n=n, colour=(0.9, 0.5, 0.2))
    return Scene((SceneObject(mesh, mat),), cam, light, viewer)


def test_exact_equals_phong_when_the_normal_is_constant() -> None:
    sc = flat_scene(Light("directional", direction=(0.1, -0.6, 1.0)), "infinite")
    r = rasterise(sc)
    a = shade(r, reference.exact_blinn)
    b = shade(r, reference.phong)
    assert a.stats.pixels_covered > 1000
    assert np.array_equal(a.rgb, b.rgb)
    np.testing.assert_allclose(a.specular, b.specular, rtol=1e-12, atol=1e-12)


def test_exact_and_phong_with_a_point_light() -> None:
    # N constant, H varies: (a) slerps H between the span ends, (b) computes it per pixel.
    # They agree exactly at the span ends; in between (a) follows the great circle, which a
    # nearby light bends away from: a far light makes them agree everywhere.
    near = flat_scene(Light("point", position=(0.2, -0.3, 1.5)), "local", n=30)
    spans = rasterise(near).objects[0].spans
    ctx = ShadeContext(near, 0, near.objects[0].material, LightingParams.of(near))
    rgb_a, spec_a = reference.float_levels(spans, ctx, "exact_blinn")
    rgb_b, _ = reference.float_levels(spans, ctx, "phong")
    ends = np.concatenate([spans.offsets[:-1], spans.offsets[1:] - 1])
    np.testing.assert_allclose(rgb_a[ends], rgb_b[ends], rtol=1e-9, atol=1e-9)
    assert spec_a.max() > 60  # a real highlight
    far = flat_scene(Light("point", position=(200.0, -300.0, 1500.0)), "local", n=30)
    cam = Camera((3, -20, 25), (0, 0, 0), (0, 0, 1), 5.0, 64, 64)
    far = Scene(far.objects, cam, far.light, "local")
    r = rasterise(far)
    a = shade(r, reference.exact_blinn)
    b = shade(r, reference.phong)
    assert np.abs(a.rgb.astype(int) - b.rgb.astype(int)).max() <= 1


def test_exact_blinn_on_one_span_matches_the_formula() -> None:
    sc = scenefile.builtin_scene("torus", 64, 64)
    r = rasterise(sc)
    spans = r.objects[0].spans
    i = int(np.argmax(spans.lengths))
    one = spans.select(np.array([i]))
    ctx = ShadeContext(sc, 0, sc.objects[0].material, LightingParams.of(sc))
    rgb, spec = reference.float_levels(one, ctx, "exact_blinn")
    m = sc.objects[0].material
    t = np.linspace(0.0, 1.0, one.n_pixels)
    n = slerp(one.n_start[0], one.n_end[0], t)
    h = slerp(one.h_start[0], one.h_end[0], t)
    p = one.p_start[0] + t[:, None] * (one.p_end[0] - one.p_start[0])
    lvec = np.asarray(sc.light.position) - p
    lvec /= np.linalg.norm(lvec, axis=1, keepdims=True)
    ndl = np.maximum(0, np.sum(n * lvec, axis=1))
    ndh = np.maximum(0, np.sum(n * h, axis=1))
    want_spec = 255 * m.k_s * sc.light.intensity * ndh**m.n
    want = 255 * np.outer(m.ambient + m.k_d * sc.light.intensity * ndl, m.colour)
    np.testing.assert_allclose(spec, want_spec, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(rgb, want + want_spec[:, None], rtol=1e-12, atol=1e-9)


def test_one_pixel_span_uses_the_start_values() -> None:
    sc = scenefile.builtin_scene("sphere", 64, 64)
    spans = rasterise(sc).objects[0].spans
    ones = spans.select(spans.lengths == 1)
    assert len(ones) > 0
    ctx = ShadeContext(sc, 0, sc.objects[0].material, LightingParams.of(sc))
    _, spec = reference.float_levels(ones, ctx, "exact_blinn")
    ndh = np.maximum(0, np.sum(ones.n_start * ones.h_start, axis=1))
    np.testing.assert_allclose(spec, 255 * 0.4 * ndh**60, rtol=1e-12, atol=1e-12)


def test_gouraud_float_interpolates_vertex_values() -> None:
    sc = scenefile.builtin_scene("sphere", 64, 64)
    r = rasterise(sc)
    spans = r.objects[0].spans
    ctx = ShadeContext(sc, 0, sc.objects[0].material, LightingParams.of(sc))
    rgb, spec = reference.float_levels(spans, ctx, "gouraud_float")
    lo = spans.offsets[:-1]
    np.testing.assert_allclose(rgb[lo], spans.g_start + spans.s_start[:, None], atol=1e-9)
    np.testing.assert_allclose(rgb[spans.offsets[1:] - 1], spans.g_end + spans.s_end[:, None])
    np.testing.assert_allclose(spec[lo], spans.s_start)


@pytest.mark.parametrize("name", scenefile.SCENE_NAMES)
def test_builtin_scenes_show_a_highlight_and_the_references_differ_sensibly(
    teapot_file, name
) -> None:
    sc = scenefile.builtin_scene(name, 96, 96)
    r = rasterise(sc)
    a = shade(r, reference.exact_blinn)
    b = shade(r, reference.phong)
    f = shade(r, reference.gouraud_float)
    assert a.specular.max() > 0.5 * 255 * sc.objects[0].material.k_s  # a visible highlight
    err_b = np.abs(a.rgb.astype(int) - b.rgb.astype(int)).max()
    err_f = np.abs(a.rgb.astype(int) - f.rgb.astype(int)).max()
    assert err_b <= err_f  # Phong is much closer to the reference than Gouraud
    assert err_f > 3


def test_float_levels_rejects_unknown_method() -> None:
    sc = scenefile.builtin_scene("sphere", 16, 16)
    spans = rasterise(sc).objects[0].spans
    ctx = ShadeContext(sc, 0, sc.objects[0].material, LightingParams.of(sc))
    with pytest.raises(ValueError, match="method = 'x' is not legal"):
        reference.float_levels(spans, ctx, "x")


# ------------------------------------------------------------------------------------------------
# the highlight test


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _sampled_max(nn: np.ndarray, h: np.ndarray, steps: int = 40) -> float:
    """max N.h over normals made the way the rasteriser makes them: slerp along two edges,
    then between them."""
    best = -1.0
    for s in np.linspace(0, 1, steps + 1):
        left = slerp(nn[0], nn[1], s)
        right = slerp(nn[0], nn[2], s)
        line = slerp(np.broadcast_to(left, (steps + 1, 3)), right, np.linspace(0, 1, steps + 1))
        best = max(best, float((line @ h).max()))
    return best


def test_highlight_inside_a_triangle_is_found_where_vertex_tests_miss_it() -> None:
    h = np.array([0.0, 0.0, 1.0])
    # vertex normals 20 degrees off H on three sides: H is in the middle of the triangle
    nn = _unit([[np.sin(0.35), 0, np.cos(0.35)], [-0.17, 0.3, 0.94], [-0.17, -0.3, 0.94]])
    n = 1000
    thr = highlight_threshold(0.5, 1.0, 0.5)
    assert (nn @ h).max() ** n < thr  # every vertex is outside the highlight
    assert triangle_may_show_highlight(nn, h, n, thr)
    assert max_dot_over_spherical_triangle(nn[None], h[None])[0] == 1.0


def test_highlight_on_an_edge_is_found() -> None:
    h = _unit([0.0, 0.02, 1.0])
    nn = _unit([[0.3, 0, 1], [-0.3, 0, 1], [0, 0.8, 0.6]])  # H near the middle of edge 0-1
    best = max_dot_over_spherical_triangle(nn[None], h[None])[0]
    assert best > 0.9997
    assert best >= _sampled_max(nn, h) - 1e-12
    far = _unit([[0.3, 0, -1], [-0.3, 0, -1], [0, 0.3, -1]])  # facing away
    assert not triangle_may_show_highlight(far, h, 10, 0.01)


# No per-example deadline: the first example pays numba's compile of the model's kernels
# and a loaded machine slows any example; max_examples bounds the run instead.
@settings(max_examples=120, deadline=None)
@given(
    st.lists(st.floats(-1, 1, allow_nan=False), min_size=12, max_size=12),
    st.integers(1, 1000),
    st.floats(1e-4, 0.5),
)
def test_highlight_test_is_exact_for_a_constant_h(coords, n, thr) -> None:
    c = np.array(coords).reshape(4, 3)
    if np.any(np.linalg.norm(c, axis=1) < 0.2):
        return
    nn, h = _unit(c[:3]), _unit(c[3])
    # keep the triangles the rasteriser produces: corners within 120 degrees of each other
    if min(nn[0] @ nn[1], nn[1] @ nn[2], nn[0] @ nn[2]) < -0.5:
        return
    exact = max_dot_over_spherical_triangle(nn[None], h[None])[0]
    sampled = _sampled_max(nn, h, 24)
    assert exact >= sampled - 1e-9  # never below what the interpolation reaches
    assert exact <= sampled + 0.02  # and tight (sampling resolution)
    may = triangle_may_show_highlight(nn, h, n, thr)
    if max(sampled, 0.0) ** n >= thr:
        assert may  # conservative: a reachable highlight is never missed


@pytest.mark.parametrize("name", scenefile.SCENE_NAMES)
def test_no_visible_highlight_lies_in_a_triangle_flagged_without_one(teapot_file, name) -> None:
    sc = scenefile.builtin_scene(name, 128, 128)
    flags = reference.object_highlight_flags(sc, 0, levels=0.5)
    frame = render(sc, reference.exact_blinn)
    covered = frame.tri_id >= 0
    in_unflagged = covered & ~flags[np.maximum(frame.tri_id, 0)]
    assert frame.specular[in_unflagged].max(initial=0.0) < 0.5
    # and the test is selective: most triangles carry no highlight
    assert flags.mean() < 0.35
    assert flags.any()


def test_highlight_test_varying_h_and_shapes() -> None:
    nn = np.tile(_unit([[0.1, 0, 1], [0, 0.1, 1], [-0.1, -0.1, 1]])[None], (2, 1, 1))
    hv = np.stack([np.tile(_unit([0, 0.5, 1]), (3, 1)), _unit([[1, 0, 0.1], [0, 0, 1], [0, 1, 0]])])
    out = triangle_may_show_highlight(nn, hv, np.array([100, 100]), 0.01)
    assert out.tolist() == [False, True]
    assert triangle_may_show_highlight(nn[0], _unit([0, 0, 1]), 5, 2.0) is False  # unreachable


@pytest.mark.parametrize(
    ("args", "pattern"),
    [
        ((np.eye(3), [0, 0, 1.0], 0, 0.1), r"n = 0 is out of range: legal range is 1\.\.1000"),
        ((np.eye(3), [0, 0, 1.0], 1001, 0.1), r"n = 1001 is out of range"),
        ((np.eye(3), [0, 0, 1.0], 2.5, 0.1), r"n = 2\.5 must be an integer"),
        ((np.eye(3), [0, 0, 1.0], 10, 0.0), r"threshold = 0\.0 is out of range"),
        ((np.eye(2), [0, 0, 1.0], 10, 0.1), r"normals shape"),
        ((np.eye(3), [0, 1.0], 10, 0.1), r"H shape"),
    ],
)
def test_highlight_test_bad_input(args, pattern) -> None:
    with pytest.raises(ValueError, match=pattern):
        triangle_may_show_highlight(*args)


def test_highlight_threshold() -> None:
    assert highlight_threshold(0.5, 1.0, 0.5) == pytest.approx(0.5 / 127.5)
    assert highlight_threshold(0.0, 1.0) == float("inf")
    with pytest.raises(ValueError, match="k_s = 2"):
        highlight_threshold(2, 1.0)


# ------------------------------------------------------------------------------------------------
# the highlight test's kernel (model.render.highlight): numpy's decisions, bit for bit


def _variants(sc: Scene):
    """The scene, and the scene with the other kind of H: a point light and a local viewer
    for a constant-H scene, a directional light and a viewer at infinity otherwise."""
    yield sc
    if sc.light.kind == "directional":
        light = Light("point", position=(2.0, -3.0, 4.0), intensity=sc.light.intensity)
        yield dataclasses.replace(sc, light=light, viewer="local")
    else:
        light = Light("directional", direction=(0.3, -0.4, 0.866), intensity=sc.light.intensity)
        yield dataclasses.replace(sc, light=light, viewer="infinite")


@pytest.mark.parametrize("name", scenefile.SCENE_NAMES)
def test_highlight_kernel_decides_as_numpy_on_every_builtin_scene(teapot_file, name) -> None:
    """Every triangle of every built-in scene, under both kinds of H, at n from 1 to 1000,
    thresholds from 0.05 to 200 levels and with back faces flipped or not: the same bools."""
    for sc in _variants(scenefile.builtin_scene(name, 96, 96)):
        for n in (sc.objects[0].material.n, 1, 7, 1000):
            scene_n = with_shininess(sc, n)
            for levels in (0.05, 0.5, 5.0, 200.0):
                for cull in (True, False):
                    want = reference.object_highlight_flags(scene_n, 0, levels, cull)
                    got = highlight.object_highlight_flags(scene_n, 0, levels, cull)
                    assert np.array_equal(got, want), (name, sc.light.kind, n, levels, cull)
        # the pipeline's call: one flag per span, each drawn triangle tested once
        spans = rasterise(sc).objects[0].spans
        per_span, flagged = highlight.span_highlight_flags(sc, spans.tri, 0, 0.5)
        want = reference.object_highlight_flags(sc, 0, 0.5, triangles=spans.tri)
        assert np.array_equal(per_span, want)
        assert flagged == np.count_nonzero(reference.object_highlight_flags(sc, 0)[
            np.unique(spans.tri)])  # fmt: skip


def _random_triangles(rng: np.random.Generator, count: int, spread: float) -> np.ndarray:
    """(count, 3, 3) unit normals: three corners within about ``spread`` radians of a random
    direction (independent directions for spread >= 3)."""
    centre = _unit(rng.normal(size=(count, 1, 3)))
    if spread >= 3:
        return _unit(rng.normal(size=(count, 3, 3)))
    return _unit(centre + spread * rng.normal(size=(count, 3, 3)))


@pytest.mark.parametrize("seed", range(4))
def test_highlight_kernel_decides_as_numpy_on_random_normals(seed) -> None:
    rng = np.random.default_rng(seed)
    for spread in (1e-3, 0.05, 0.3, 1.0, 3.0):
        nn = _random_triangles(rng, 4000, spread)
        h_const = _unit(rng.normal(size=3))
        # per-vertex H: near a common direction (a point light), or random
        h_vertex = _unit(h_const + (0.05 if seed % 2 else 1.0) * rng.normal(size=(4000, 3, 3)))
        for n in (1, 3, 40, 1000):
            for thr in (1e-6, 0.002, 0.3, 0.999999, 1.0, 1.5):
                for h in (h_const, h_vertex):
                    want = triangle_may_show_highlight(nn, h, n, thr)
                    got = highlight.triangle_may_show_highlight(nn, h, n, thr)
                    assert np.array_equal(got, want), (seed, spread, n, thr, h.shape)


def test_highlight_kernel_decides_as_numpy_on_the_edge_cases(monkeypatch) -> None:
    """H on a corner, on an edge, at the centre, opposite; flat, half-flat, antipodal and
    coplanar corners; determinants at numpy's 1e-12 cut (where the kernel's triple products
    and LAPACK may disagree: it asks numpy, and that path is taken); thresholds whose angle is
    0 (threshold 1) or just above."""
    rng = np.random.default_rng(5)
    base = _random_triangles(rng, 300, 0.2)
    cases, hs = [], []
    for tri in base:
        mid = _unit(tri[0] + tri[1])
        centre = _unit(tri.sum(axis=0))
        for h in (tri[0], tri[2], mid, centre, -centre, _unit(mid + 1e-9 * centre)):
            cases.append(tri)
            hs.append(h)
        flat = np.tile(tri[0], (3, 1))
        half = np.stack([tri[0], tri[0], tri[1]])
        opposite = np.stack([tri[0], -tri[0], tri[1]])
        ring = _unit(np.stack([tri[0], tri[1], tri[0] + tri[1]]))  # coplanar with the origin
        for odd in (flat, half, opposite, ring):
            for h in (tri[0], mid, centre):
                cases.append(odd)
                hs.append(h)
    # thin triangles: det = sin^2(e) about 1e-12 at e = 1e-6, on both sides of the cut
    for e in np.linspace(0.95e-6, 1.05e-6, 41):
        thin = np.array([[1.0, 0, 0], [np.cos(e), np.sin(e), 0], [np.cos(e), 0, np.sin(e)]])
        for h in (_unit([1.0, e / 3, e / 3]), _unit([1.0, -e, e / 2]), thin[1]):
            cases.append(_unit(thin))
            hs.append(h)
    nn = np.array(cases)
    hv = np.repeat(np.array(hs)[:, None, :], 3, axis=1)  # per vertex, all three equal
    asked = []
    numpy_test = highlight.reference_triangle_test

    def counting(*args):
        asked.append(len(args[0]))
        return numpy_test(*args)

    monkeypatch.setattr(highlight, "reference_triangle_test", counting)
    for n in (1, 2, 50, 1000):
        for thr in (1.0, 1.0 - 1e-15, 0.9999999, 0.5, 1e-3):
            for h in (np.array(hs), hv):
                for t in range(0, len(nn), 997):  # constant H: one H at a time, many triangles
                    pick = slice(None) if h.ndim == 3 else slice(t, t + 997)
                    hh = h[pick] if h.ndim == 3 else h[t]
                    want = triangle_may_show_highlight(nn[pick], hh, n, thr)
                    got = highlight.triangle_may_show_highlight(nn[pick], hh, n, thr)
                    assert np.array_equal(got, want), (n, thr, h.ndim, t)
                    if h.ndim == 3:
                        break
    assert asked, "no triangle was unsure: the thin cases no longer reach numpy's cut"


def test_highlight_kernel_bad_input() -> None:
    with pytest.raises(ValueError, match="normals shape"):
        highlight.triangle_may_show_highlight(np.eye(3), [0, 0, 1.0], 10, 0.1)
    with pytest.raises(ValueError, match=r"threshold = 0\.0 is out of range"):
        highlight.triangle_may_show_highlight(np.eye(3)[None], [0, 0, 1.0], 10, 0.0)
    sc = scenefile.builtin_scene("sphere", 32, 32)
    with pytest.raises(ValueError, match="triangle index 99999 is out of range"):
        highlight.span_highlight_flags(sc, np.array([0, 99999]))
