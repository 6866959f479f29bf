# SPDX-License-Identifier: Apache-2.0
"""Float reference shaders, the 8-bit quantisation and the per-triangle highlight test."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from model.render import reference, scenefile
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
def test_builtin_scenes_show_a_highlight_and_the_references_differ_sensibly(name) -> None:
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
def test_no_visible_highlight_lies_in_a_triangle_flagged_without_one(name) -> None:
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
