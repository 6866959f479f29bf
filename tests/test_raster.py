# SPDX-License-Identifier: Apache-2.0
"""The float rasteriser: fill rule, coverage, depth test, culling, span set-up, slerp, shaders."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from model.render import reference, scenefile
from model.render.raster import rasterise, screen_spans
from model.render.scene import Camera, Light, Material, Mesh, Scene, SceneObject
from model.render.shade import ShadeResult, per_span, render, shade
from model.render.spans import SPAN_ARRAYS, Spans
from model.render.vectors import LightingParams, lighting_vectors, slerp

# ------------------------------------------------------------------------------------------------
# helpers


def coverage_count(xy, width: int, height: int) -> np.ndarray:
    """How many spans cover each pixel."""
    _, y, xs, xe = screen_spans(np.asarray(xy, dtype=np.float64), width, height)
    count = np.zeros((height, width), dtype=np.int64)
    for row, a, b in zip(y, xs, xe, strict=True):
        count[row, a : b + 1] += 1
    return count


def inside(xy: np.ndarray, px: np.ndarray, py: np.ndarray, margin: float) -> np.ndarray:
    """Pixel centres strictly inside a triangle by more than ``margin`` (any winding)."""
    (x0, y0), (x1, y1), (x2, y2) = xy
    area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    sign = 1.0 if area > 0 else -1.0
    e0 = sign * ((x1 - x0) * (py - y0) - (y1 - y0) * (px - x0)) / np.hypot(x1 - x0, y1 - y0)
    e1 = sign * ((x2 - x1) * (py - y1) - (y2 - y1) * (px - x1)) / np.hypot(x2 - x1, y2 - y1)
    e2 = sign * ((x0 - x2) * (py - y2) - (y0 - y2) * (px - x2)) / np.hypot(x0 - x2, y0 - y2)
    return (e0 > margin) & (e1 > margin) & (e2 > margin)


def flat_square_scene(
    size: float = 1.0, width: int = 64, height: int = 64, normals=None, material=None, **kw
) -> Scene:
    """A square [-size/2, size/2]^2 at z = 0 seen straight from above by a 90-degree camera at
    distance 1: world x maps to screen x = W/2 + (H/2) x exactly."""
    h = size / 2
    v = np.array([[-h, -h, 0], [h, -h, 0], [h, h, 0], [-h, h, 0]], dtype=np.float64)
    t = np.array([[0, 1, 2], [0, 2, 3]])
    n = np.tile([0, 0, 1.0], (4, 1)) if normals is None else normals
    mesh = Mesh(v, t, n, name="square")
    cam = Camera((0, 0, 1), (0, 0, 0), (0, 1, 0), 90.0, width, height)
    light = kw.pop("light", Light("directional", direction=(0.3, 0.2, 1.0)))
    viewer = kw.pop("viewer", "infinite")
    return Scene((SceneObject(mesh, material or Material()),), cam, light, viewer, **kw)


def constant_shader(value: int):
    def shader(spans, ctx):
        return np.full((spans.n_pixels, 3), value, dtype=np.uint8)

    return shader


# ------------------------------------------------------------------------------------------------
# fill rule and coverage


def test_axis_aligned_square_pixel_count_through_the_pipeline() -> None:
    # world [-0.5, 0.5]^2 -> screen [16, 48)^2 -> exactly 32 x 32 pixels, none twice
    sc = flat_square_scene(1.0, 64, 64)
    frame = render(sc, constant_shader(200))
    assert frame.stats.pixels_covered == 32 * 32
    assert frame.coverage[16:48, 16:48].all()
    assert frame.coverage.sum() == 32 * 32
    assert (frame.rgb[frame.coverage] == 200).all()
    assert (frame.rgb[~frame.coverage] == 0).all()
    r = rasterise(sc)
    assert r.objects[0].spans.n_pixels == 32 * 32  # no pixel rasterised twice


@pytest.mark.parametrize(
    ("x0", "x1", "y0", "y1", "expected"),
    [
        (2.0, 10.0, 3.0, 7.0, 8 * 4),  # pixel corners: no centre on an edge
        (2.5, 10.5, 3.5, 7.5, 8 * 4),  # centres on every edge: left/top in, right/bottom out
        (2.5, 3.5, 3.5, 4.5, 1),  # exactly one pixel centre, on the top-left corner
        (2.4, 2.6, 3.0, 9.0, 6),  # a sliver one pixel wide: 1-pixel spans
        (2.6, 2.9, 3.0, 9.0, 0),  # a sliver between two pixel centres: nothing
    ],
)
def test_square_of_two_triangles_covers_the_expected_pixels(x0, x1, y0, y1, expected) -> None:
    for diagonal in (0, 1):
        if diagonal == 0:
            tris = [[(x0, y0), (x1, y0), (x1, y1)], [(x0, y0), (x1, y1), (x0, y1)]]
        else:
            tris = [[(x0, y0), (x1, y0), (x0, y1)], [(x1, y0), (x1, y1), (x0, y1)]]
        count = coverage_count(tris, 16, 16)
        assert count.max() <= 1
        assert count.sum() == expected


def test_fan_with_vertices_on_pixel_centres_covers_each_pixel_once() -> None:
    # a 6 x 6 grid of vertices at pixel centres, every cell split along alternating diagonals:
    # every shared edge passes exactly through pixel centres
    g = np.arange(6) * 3 + 1.5
    tris = []
    for i in range(5):
        for j in range(5):
            a, b = (g[i], g[j]), (g[i + 1], g[j])
            c, d = (g[i + 1], g[j + 1]), (g[i], g[j + 1])
            tris += [[a, b, c], [a, c, d]] if (i + j) % 2 else [[a, b, d], [b, c, d]]
    count = coverage_count(tris, 20, 20)
    assert count.max() == 1
    # the union is [1.5, 16.5)^2 in centres -> pixels 1..15 in x and y
    assert count[1:16, 1:16].all()
    assert count.sum() == 15 * 15


# No per-example deadline: the first example pays numba's compile of the model's kernels
# and a loaded machine slows any example; max_examples bounds the run instead.
@settings(max_examples=150, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(-3, 27, allow_nan=False), st.floats(-3, 27, allow_nan=False)),
        min_size=4,
        max_size=4,
    ),
    st.booleans(),
)
def test_two_triangles_sharing_an_edge_cover_each_pixel_once(points, snap) -> None:
    pts = np.array(points)
    if snap:  # put the vertices on pixel centres and corners: the hard cases for the rule
        pts = np.round(pts * 2) / 2
    a, b, c, d = pts
    t1, t2 = np.array([a, b, c]), np.array([a, c, d])
    # the shared edge a-c must separate b and d (a proper pair, not overlapping triangles)
    side = lambda p: np.sign((c[0] - a[0]) * (p[1] - a[1]) - (c[1] - a[1]) * (p[0] - a[0]))  # noqa: E731
    if side(b) * side(d) >= 0:
        return
    width = height = 24
    count = coverage_count([t1, t2], width, height)
    assert count.max() <= 1
    px, py = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    strictly = inside(t1, px, py, 1e-9) | inside(t2, px, py, 1e-9)
    assert (count[strictly] == 1).all()
    # nothing outside the two triangles (allowing centres on their outer edges)
    near = inside(t1, px, py, -1e-9) | inside(t2, px, py, -1e-9)
    assert (count[~near] == 0).all()


def test_spans_are_clipped_to_the_image() -> None:
    count = coverage_count([[(-10, -10), (30, -10), (-10, 30)]], 8, 8)
    assert count.shape == (8, 8)
    assert count.max() == 1
    # the hypotenuse x + y = 20 is far outside: every pixel covered
    assert count.sum() == 64


# ------------------------------------------------------------------------------------------------
# culling, depth test


def two_squares_scene(z_first: float, z_second: float, cull: bool = True) -> Scene:
    def square(z, offset):
        v = np.array([[-0.4, -0.4, z], [0.4, -0.4, z], [0.4, 0.4, z], [-0.4, 0.4, z]])
        v[:, 0] += offset
        return Mesh(v, [[0, 1, 2], [0, 2, 3]], np.tile([0, 0, 1.0], (4, 1)))

    objs = (
        SceneObject(square(z_first, -0.15), Material(n=5, colour=(1, 0, 0))),
        SceneObject(square(z_second, 0.15), Material(n=7, colour=(0, 1, 0))),
    )
    cam = Camera((0, 0, 2), (0, 0, 0), (0, 1, 0), 60.0, 48, 48)
    return Scene(objs, cam, Light("directional", direction=(0, 0, 1)), "infinite")


def test_depth_test_nearer_wins_in_either_order() -> None:
    for z1, z2, front in [(0.2, 0.0, 0), (0.0, 0.2, 1)]:
        frame = render(two_squares_scene(z1, z2), reference.exact_blinn)
        # the middle column lies in both squares (x in [-0.25, 0.25]): the nearer one is seen
        assert (frame.obj_id[18:30, 22:27] == front).all()
        assert frame.rgb[24, 24, front] > frame.rgb[24, 24, 1 - front]
        assert set(np.unique(frame.obj_id)) == {-1, 0, 1}


def test_depth_ties_keep_the_first() -> None:
    frame = render(two_squares_scene(0.0, 0.0), constant_shader(9))
    assert frame.obj_id[24, 24] == 0
    # and within one mesh: the same triangle twice -> the first one wins
    v = np.array([[-0.5, -0.5, 0], [0.5, -0.5, 0], [0, 0.5, 0]])
    mesh = Mesh(v, [[0, 1, 2], [0, 1, 2]], np.tile([0, 0, 1.0], (3, 1)))
    sc = Scene((SceneObject(mesh, Material()),), Camera((0, 0, 2), (0, 0, 0), (0, 1, 0)))
    sc = sc.with_resolution(32, 32)
    frame = render(sc, constant_shader(9))
    assert set(np.unique(frame.tri_id)) == {-1, 0}
    # the hidden duplicate is not shaded
    assert frame.stats.spans_shaded * 2 == frame.stats.spans


def test_hidden_spans_are_skipped_unless_asked() -> None:
    sc = two_squares_scene(0.0, 0.2)
    r = rasterise(sc)
    a = shade(r, constant_shader(1))
    b = shade(r, constant_shader(1), skip_hidden_spans=False)
    assert np.array_equal(a.rgb, b.rgb) and np.array_equal(a.obj_id, b.obj_id)
    assert a.stats.pixels_shaded <= b.stats.pixels_shaded
    assert b.stats.spans_shaded == b.stats.spans


def test_back_faces_are_culled_or_drawn_two_sided() -> None:
    v = np.array([[-0.5, -0.5, 0], [0, 0.5, 0], [0.5, -0.5, 0]])  # clockwise seen from +z
    mesh = Mesh(v, [[0, 1, 2]], np.tile([0, 0, -1.0], (3, 1)))
    sc = Scene(
        (SceneObject(mesh, Material(ambient=0, k_s=0)),),
        Camera((0, 0, 2), (0, 0, 0), (0, 1, 0), 60.0, 32, 32),
        Light("directional", direction=(0, 0, 1)),
    )
    culled = render(sc, reference.exact_blinn)
    assert culled.stats.pixels_covered == 0 and culled.stats.triangles_culled == 1
    two_sided = render(sc, reference.exact_blinn, cull_backfaces=False)
    assert two_sided.stats.pixels_covered > 0
    # the normal (0,0,-1) is flipped towards the viewer: the face is lit
    assert two_sided.rgb[two_sided.coverage, 0].min() > 100


def test_triangles_behind_the_eye_are_dropped() -> None:
    v = np.array([[-0.5, -0.5, 3], [0.5, -0.5, 3], [0, 0.5, 0]])  # two corners behind the eye
    mesh = Mesh(v, [[0, 1, 2]], np.tile([0, 0, 1.0], (3, 1)))
    sc = Scene((SceneObject(mesh, Material()),), Camera((0, 0, 2), (0, 0, 0), (0, 1, 0)))
    frame = render(sc, constant_shader(5))
    assert frame.stats.triangles_clipped == 1 and frame.stats.pixels_covered == 0


# ------------------------------------------------------------------------------------------------
# span set-up


def test_span_ends_are_unit_and_consistent() -> None:
    sc = scenefile.builtin_scene("torus", 96, 96)
    spans = rasterise(sc).objects[0].spans
    assert len(spans) > 100
    assert np.all(spans.x_start <= spans.x_end)
    assert (spans.lengths == 1).any()  # 1-pixel spans occur and are legal
    for v in (spans.n_start, spans.n_end, spans.h_start, spans.h_end):
        np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1.0, atol=1e-12)
    assert np.all(spans.z_start > 0) and np.all(spans.z_end > 0)
    # the linearly interpolated normal points the same way as the spherical one
    nl = spans.nlin_start / np.linalg.norm(spans.nlin_start, axis=1, keepdims=True)
    assert np.einsum("sk,sk->s", nl, spans.n_start).min() > 0.99
    # H at a span end is the half-vector at that end's world position (local viewer, point light)
    lp = LightingParams.of(sc)
    _, _, h = lighting_vectors(spans.p_end, lp)
    np.testing.assert_allclose(h, spans.h_end, atol=1e-12)
    one = spans.span(3)
    assert one.length == one.intervals + 1
    assert one.obj == 0 and isinstance(one.s_start, float)


def test_span_values_along_an_edge_are_the_slerped_vertex_normals() -> None:
    v = np.array([[-0.5, -0.5, 0], [0.5, -0.5, 0], [-0.5, 0.5, 0]])
    nrm = np.array([[0.3, 0, 1], [0, 0.3, 1], [-0.3, -0.3, 1]])
    mesh = Mesh(v, [[0, 1, 2]], nrm)
    # 34 x 34 image, fov 90, distance 1: screen = 17 + 17 x -> the corners land on pixel centres
    # (8.5, 8.5) [vertex 2, top], (8.5, 25.5) [vertex 0] and (25.5, 25.5) [vertex 1]
    cam = Camera((0, 0, 1), (0, 0, 0), (0, 1, 0), 90.0, 34, 34)
    sc = Scene((SceneObject(mesh, Material()),), cam, Light("directional", direction=(0, 0, 1)))
    spans = rasterise(sc).objects[0].spans
    # the top vertex's row is an empty span (zero width); the bottom edge row is excluded
    assert spans.y.min() == 9 and spans.y.max() == 24
    assert np.all(spans.x_start == 8)
    # the left edge passes through the first pixel centre of every row: N = slerp(N2, N0, s)
    s_edge = (spans.y + 0.5 - 8.5) / 17.0
    np.testing.assert_allclose(
        spans.n_start, slerp(mesh.normals[2], mesh.normals[0], s_edge), atol=1e-12
    )
    np.testing.assert_allclose(spans.p_start[:, 0], -0.5, atol=1e-12)


# ------------------------------------------------------------------------------------------------
# slerp


unit_vectors = st.tuples(
    st.floats(-1, 1, allow_nan=False), st.floats(-1, 1, allow_nan=False), st.floats(-1, 1)
).filter(lambda v: np.linalg.norm(v) > 0.1)


# No per-example deadline: the first example pays numba's compile of the model's kernels
# and a loaded machine slows any example; max_examples bounds the run instead.
@settings(max_examples=200, deadline=None)
@given(unit_vectors, unit_vectors, st.floats(0, 1))
def test_slerp_properties(a, b, t) -> None:
    a = np.array(a) / np.linalg.norm(a)
    b = np.array(b) / np.linalg.norm(b)
    np.testing.assert_array_equal(slerp(a, b, 0.0), a)
    np.testing.assert_array_equal(slerp(a, b, 1.0), b)
    p = slerp(a, b, t)
    assert abs(np.linalg.norm(p) - 1.0) < 1e-12
    omega = np.arctan2(np.linalg.norm(np.cross(a, b)), a @ b)
    if omega < np.pi - 1e-6:
        # constant angular speed: angle(a, p) = t * omega and angle(p, b) = (1 - t) * omega
        ang = lambda u, v: np.arctan2(np.linalg.norm(np.cross(u, v)), u @ v)  # noqa: E731
        assert abs(ang(a, p) - t * omega) < 1e-9
        assert abs(ang(p, b) - (1 - t) * omega) < 1e-9
        # on the great circle through a and b
        assert abs(np.cross(a, b) @ p) < 1e-9 * max(1.0, np.linalg.norm(np.cross(a, b)))


def test_slerp_degenerate_cases() -> None:
    a = np.array([0.0, 0.6, 0.8])
    # identical and nearly identical
    np.testing.assert_allclose(slerp(a, a, 0.37), a, atol=1e-15)
    b = a + np.array([1e-12, 0, 0])
    b /= np.linalg.norm(b)
    assert abs(np.linalg.norm(slerp(a, b, 0.5)) - 1) < 1e-15
    # antipodal: a unit path of constant speed from a to -a, deterministic
    ts = np.linspace(0, 1, 11)
    path = slerp(a, -a, ts)
    np.testing.assert_allclose(np.linalg.norm(path, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(path @ a, np.cos(np.pi * ts), atol=1e-12)
    np.testing.assert_array_equal(path[-1], -a)
    assert np.all(np.isfinite(slerp([0, 0, 1.0], [0, 0, -1.0], 0.5)))


def test_slerp_broadcasts() -> None:
    out = slerp([1.0, 0, 0], [0, 1.0, 0], np.linspace(0, 1, 5))
    assert out.shape == (5, 3)
    np.testing.assert_allclose(out[2], [np.sqrt(0.5), np.sqrt(0.5), 0], atol=1e-15)


# ------------------------------------------------------------------------------------------------
# shader interface and statistics


def test_per_span_adaptor_equals_batch_shader() -> None:
    sc = scenefile.builtin_scene("sphere", 48, 48)
    r = rasterise(sc)

    def one(span, ctx):
        res = reference.exact_blinn(
            Spans(
                span.obj,
                *[np.asarray(getattr(span, f))[None] for f in SPAN_ARRAYS],
            ),
            ctx,
        )
        return ShadeResult(res.rgb, res.specular, {"calls": 1})

    a = shade(r, reference.exact_blinn)
    b = shade(r, per_span(one))
    assert np.array_equal(a.rgb, b.rgb)
    np.testing.assert_allclose(a.specular, b.specular)
    assert b.stats.counters["calls"] == b.stats.spans_shaded


def test_bad_shader_output_is_refused() -> None:
    sc = flat_square_scene(1.0, 16, 16)
    with pytest.raises(ValueError, match=r"shader output shape = .* legal shape is"):
        render(sc, lambda spans, ctx: np.zeros((spans.n_pixels, 4), dtype=np.uint8))
    with pytest.raises(ValueError, match="dtype"):
        render(sc, lambda spans, ctx: np.zeros((spans.n_pixels, 3)))
    with pytest.raises(ValueError, match="screen_xy shape"):
        screen_spans(np.zeros((2, 3)), 8, 8)


def test_stats() -> None:
    sc = scenefile.builtin_scene("quad", 64, 64)
    frame = render(sc, reference.exact_blinn)
    st_ = frame.stats
    assert st_.n_values == (1000,)
    r = rasterise(sc)
    lengths = r.objects[0].spans.lengths
    assert st_.longest_span == lengths.max()
    assert st_.pixels_shaded == lengths.sum()  # nothing hidden on a dome seen from above
    assert st_.pixels_covered == frame.coverage.sum() <= st_.pixels_shaded
    assert st_.triangles == 2048 and st_.triangles_shaded <= 2048
    assert st_.pixels_per_second > 0
    assert set(st_.as_dict()) >= {"spans", "longest_span", "n_values"}
