# SPDX-License-Identifier: Apache-2.0
"""Scenes: the built-in scenes are valid, the teapot tessellation, OBJ/PLY through trimesh,
bad input."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from model.render import meshes, meshfile, scenefile
from model.render.scene import Camera, Light, Material, Mesh, Scene, SceneObject


def _check_mesh(mesh: Mesh) -> None:
    assert np.all(np.isfinite(mesh.vertices))
    assert np.all(np.isfinite(mesh.normals))
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-12)
    assert mesh.triangles.min() >= 0 and mesh.triangles.max() < mesh.n_vertices
    t = mesh.triangles
    assert np.all((t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 0] != t[:, 2]))


def _face_normal_agreement(mesh: Mesh) -> float:
    """Share of triangles whose winding normal agrees with their mean vertex normal."""
    p = mesh.vertices[mesh.triangles]
    fn = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    vn = mesh.normals[mesh.triangles].sum(axis=1)
    return float(np.mean(np.einsum("tk,tk->t", fn, vn) > 0))


@pytest.mark.parametrize("name", scenefile.SCENE_NAMES)
def test_builtin_scenes_are_valid(name: str, teapot_file) -> None:
    sc = scenefile.builtin_scene(name, width=64, height=48)
    assert sc.camera.width == 64 and sc.camera.height == 48
    assert sc.name == name
    for obj in sc.objects:
        _check_mesh(obj.mesh)
        assert _face_normal_agreement(obj.mesh) > 0.99
        assert 1 <= obj.material.n <= 1000
        assert obj.material.k_s > 0
    assert sc.n_values == tuple(sorted({o.material.n for o in sc.objects}))


def test_quad_scene_has_a_tight_highlight_exponent() -> None:
    sc = scenefile.builtin_scene("quad")
    assert sc.objects[0].material.n >= 900
    lo, hi = sc.objects[0].mesh.bounds()
    assert (hi - lo)[:2].min() >= 3.0  # large
    assert (hi - lo)[2] <= 0.15 * (hi - lo)[:2].min()  # flat-ish
    assert sc.light.kind == "point" and sc.viewer == "local"


def test_sphere_and_torus_normals_are_exact() -> None:
    s = meshes.sphere_mesh(2.0, 2)
    np.testing.assert_allclose(s.normals, s.vertices / 2.0, atol=1e-12)
    t = meshes.torus_mesh(1.0, 0.4, 16, 8)
    ring = t.vertices.copy()
    ring[:, 2] = 0
    ring = ring / np.linalg.norm(ring, axis=1, keepdims=True)  # the tube centre direction
    np.testing.assert_allclose(t.vertices - ring * 1.0, 0.4 * t.normals, atol=1e-12)
    # the torus is closed: every edge shared by two triangles
    tm = trimesh.Trimesh(t.vertices, t.triangles, process=False)
    assert tm.is_watertight and tm.is_winding_consistent and tm.volume > 0


def test_teapot_file_has_28_patches(teapot_file) -> None:
    patches = meshes.read_bezier_patches(teapot_file)
    assert patches.shape == (28, 4, 4, 3)


def test_teapot_tessellation(teapot_file) -> None:
    steps = 6
    mesh = meshes.teapot_mesh(steps)
    _check_mesh(mesh)
    full = 28 * 2 * steps * steps
    # only the triangles collapsing at the lid pole are dropped (4 patches x steps)
    assert full - 4 * steps <= mesh.n_triangles <= full
    tm = trimesh.Trimesh(mesh.vertices, mesh.triangles, process=False)
    assert tm.is_winding_consistent
    edges = np.sort(tm.edges, axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert counts.max() <= 2  # manifold
    # closed-ish: only the open base, the handle and spout ends and the lid seam are boundaries
    assert np.mean(counts == 1) < 0.06
    assert tm.volume > 0  # oriented outwards
    assert _face_normal_agreement(mesh) == 1.0
    # the lid knob's pole: one welded vertex whose normal points straight up
    top = np.argmax(mesh.vertices[:, 2])
    np.testing.assert_allclose(mesh.normals[top], [0, 0, 1], atol=1e-6)


def test_degenerate_patch_pole_gets_a_finite_normal() -> None:
    # a dome-like patch whose whole first row is one point (a pole, dS/dv = 0 there); the second
    # row at the same height makes the tangent plane at the pole horizontal
    ctrl = np.zeros((4, 4, 3))
    for i, z in enumerate([1.0, 1.0, 0.8, 0.5]):
        r = i / 3
        for j in range(4):
            a = j / 3 * np.pi / 2
            ctrl[i, j] = [r * np.cos(a), r * np.sin(a), z]
    mesh = meshes.tessellate_patches(ctrl[None], steps=4)
    _check_mesh(mesh)
    apex = np.argmax(mesh.vertices[:, 2])
    assert mesh.normals[apex][2] > 0.99


def test_flat_patch_normal() -> None:
    g = np.linspace(0, 1, 4)
    x, y = np.meshgrid(g, g, indexing="ij")
    ctrl = np.stack([x, y, np.zeros_like(x)], -1)
    mesh = meshes.tessellate_patches(ctrl[None], steps=3)
    np.testing.assert_allclose(mesh.normals, np.tile([0, 0, 1.0], (mesh.n_vertices, 1)))
    assert mesh.n_triangles == 18


def _small_trimesh(with_normals: bool) -> trimesh.Trimesh:
    verts = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.2]]
    faces = [[0, 1, 2], [1, 3, 2]]
    if with_normals:
        vn = [[0, 0.6, 0.8], [0.6, 0, 0.8], [0, 0, 1], [0.8, 0, 0.6]]
        return trimesh.Trimesh(verts, faces, vertex_normals=vn, process=False)
    return trimesh.Trimesh(verts, faces, process=False)


@pytest.mark.parametrize("ext", ["obj", "ply"])
def test_mesh_file_round_trip_keeps_normals(tmp_path, ext: str) -> None:
    tm = _small_trimesh(with_normals=True)
    path = tmp_path / f"m.{ext}"
    tm.export(path, **({"include_normals": True} if ext == "obj" else {"vertex_normal": True}))
    mesh = meshfile.load_mesh(path)
    np.testing.assert_allclose(mesh.vertices, tm.vertices, atol=1e-6)
    np.testing.assert_array_equal(mesh.triangles, tm.faces)
    np.testing.assert_allclose(mesh.normals, tm.vertex_normals, atol=1e-6)
    assert mesh.name == "m"


@pytest.mark.parametrize("ext", ["obj", "ply"])
def test_mesh_file_without_normals_gets_trimesh_normals(tmp_path, ext: str) -> None:
    tm = _small_trimesh(with_normals=False)
    path = tmp_path / f"m.{ext}"
    tm.export(path)
    mesh = meshfile.load_mesh(path)
    _check_mesh(mesh)
    assert np.all(mesh.normals[:, 2] > 0.9)  # the faces face +z
    # a scene around the loaded mesh renders
    sc = meshes.scene_from_mesh(mesh, width=16, height=16)
    assert sc.objects[0].mesh is mesh


def test_load_mesh_bad_input(tmp_path) -> None:
    with pytest.raises(ValueError, match="does not exist"):
        meshfile.load_mesh(tmp_path / "missing.obj")
    with pytest.raises(ValueError, match=r"legal suffixes are \.obj, \.ply, \.off, \.stl"):
        meshfile.load_mesh(tmp_path / "m.xyz")
    with pytest.raises(ValueError, match="fetch-teapot"):
        meshes.read_bezier_patches(tmp_path / "none.bez")
    bad = tmp_path / "bad.bez"
    bad.write_text("BBP\n1 2 3\n")
    with pytest.raises(ValueError, match="multiple of 48"):
        meshes.read_bezier_patches(bad)


@pytest.mark.parametrize(
    ("make", "pattern"),
    [
        (lambda: scenefile.builtin_scene("cube"), r"name = 'cube' is not legal: legal values are"),
        (lambda: Material(n=0), r"n = 0 is out of range: legal range is 1\.\.1000"),
        (lambda: Material(n=1001), r"n = 1001 is out of range: legal range is 1\.\.1000"),
        (lambda: Material(n=2.5), r"n = 2\.5 must be an integer"),
        (lambda: Material(k_s=1.5), r"k_s = 1\.5 is out of range: legal range is 0"),
        (lambda: Material(colour=(1, 2, 0)), r"colour\[1\] = 2 is out of range"),
        (lambda: Camera(width=0), r"width = 0 is out of range: legal range is 1\.\.4096"),
        (lambda: Camera(height=100000), r"height = 100000 is out of range"),
        (lambda: scenefile.builtin_scene("sphere", width=-5), r"width = -5 is out of range"),
        (lambda: Camera(eye=(1, 1, 1), target=(1, 1, 1)), r"cannot be normalised"),
        (lambda: Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 0, 1)), r"parallel"),
        (lambda: Camera(fov_y=180), r"fov_y = 180 is out of range"),
        (lambda: Light(direction=(0, 0, 0)), r"direction = \(0, 0, 0\) cannot be normalised"),
        (lambda: Light(kind="spot"), r"kind = 'spot' is not legal"),
        (lambda: Light(intensity=-1), r"intensity = -1 is out of range"),
        (lambda: Light(position=(0, np.nan, 0)), r"finite 3-vector"),
        (lambda: Scene((), Camera()), r"at least one object"),
    ],
)
def test_bad_input_is_refused(make, pattern: str) -> None:
    with pytest.raises(ValueError, match=pattern):
        make()


def test_bad_meshes_are_refused() -> None:
    v = np.eye(3)
    t = np.array([[0, 1, 2]])
    with pytest.raises(ValueError, match=r"normals\[1\] = .* cannot be normalised"):
        Mesh(v, t, np.array([[0, 0, 1.0], [0, 0, 0], [0, 0, 1]]))
    with pytest.raises(
        ValueError, match=r"triangle index = 3 is out of range: legal range is 0\.\.2"
    ):
        Mesh(v, np.array([[0, 1, 3]]), v)
    with pytest.raises(ValueError, match="normals shape"):
        Mesh(v, t, v[:2])
    with pytest.raises(ValueError, match="scene"):
        Scene((SceneObject(Mesh(v, t, v), Material()),), viewer="scene")


def test_vectors_are_normalised_and_frozen() -> None:
    light = Light(direction=(0, 0, 5))
    assert light.direction == (0.0, 0.0, 1.0)
    mesh = Mesh(np.eye(3), [[0, 1, 2]], np.eye(3) * 3)
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0)
    with pytest.raises(ValueError):
        mesh.vertices[0, 0] = 5.0  # read-only arrays
    with pytest.raises(AttributeError):
        light.intensity = 2.0  # type: ignore[misc]
