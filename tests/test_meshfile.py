# SPDX-License-Identifier: Apache-2.0
"""Mesh files as people have them: every format, messy geometry repaired or reported, any up axis.

Each defect has its own small mesh, made here (as arrays or as the text of a file), and the
repair is checked against what the defect is: which faces go, which vertices, which normals.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest
import trimesh

from model.render import meshes, meshfile
from model.render.meshfile import Repairs, auto_up, orient, read_mesh, repair, up_rotation

FORMATS = ("obj", "ply", "off", "stl", "glb")

# A unit square in z = 0 split into two triangles facing +z, and a fifth vertex off the square.
SQUARE_V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [5, 5, 5]], dtype=float)
SQUARE_F = np.array([[0, 1, 2], [0, 2, 3]])


def _write_obj(path: Path, vertices, faces, normals=None) -> Path:
    """An OBJ written by hand (1-based faces; with ``normals``, ``vn`` lines and ``f a//a``)."""
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(vertices, dtype=float).tolist()]
    if normals is not None:
        lines += [f"vn {x!r} {y!r} {z!r}" for x, y, z in np.asarray(normals, float).tolist()]
        lines += ["f " + " ".join(f"{i + 1}//{i + 1}" for i in face) for face in faces]
    else:
        lines += ["f " + " ".join(str(i + 1) for i in face) for face in faces]
    path.write_text("\n".join(lines) + "\n")
    return path


# ------------------------------------------------------------------------------ repairs, one each
def test_clean_mesh_is_untouched() -> None:
    v, f, n, fixes = repair(SQUARE_V[:4], SQUARE_F, np.tile([0.0, 0, 1], (4, 1)))
    np.testing.assert_array_equal(n, np.tile([0.0, 0, 1], (4, 1)))
    np.testing.assert_array_equal(v, SQUARE_V[:4])
    np.testing.assert_array_equal(f, SQUARE_F)
    assert fixes == Repairs() and fixes.summary() == "nothing to repair"


def test_degenerate_faces_are_dropped() -> None:
    faces = np.array([[0, 1, 2], [0, 0, 1], [0, 1, 1], [0, 2, 3], [0, 1, 5]])
    v = np.vstack([SQUARE_V[:4], [[2.0, 0, 0]]])  # vertex 4: on the line through 0 and 1
    faces[4] = [0, 1, 4]  # collinear corners: no area
    _, f2, _, fixes = repair(v, faces, np.tile([0.0, 0, 1], (5, 1)))
    assert fixes.degenerate_faces == 3
    np.testing.assert_array_equal(f2, SQUARE_F)  # the two real faces, in file order
    assert fixes.unreferenced_vertices == 1  # vertex 4 was only in a degenerate face
    assert "3 degenerate faces dropped" in fixes.summary()


def test_duplicate_faces_are_dropped_and_a_reversed_face_kept() -> None:
    faces = np.array([[0, 1, 2], [1, 2, 0], [0, 2, 3], [2, 3, 0], [0, 2, 1]])
    _, f, _, fixes = repair(SQUARE_V[:4], faces, None)
    assert fixes.duplicate_faces == 2  # two rotations of earlier faces
    assert f.shape == (3, 3)  # [0, 1, 2], [0, 2, 3] and the back face [0, 2, 1]
    assert "2 duplicate faces dropped" in fixes.summary()


def test_unreferenced_vertices_are_removed_and_faces_renumbered() -> None:
    v = np.vstack([[[9.0, 9, 9]], SQUARE_V[:4], [[7.0, 7, 7]]])  # 0 and 5 unused
    v2, f2, n2, fixes = repair(v, SQUARE_F + 1, np.tile([0.0, 0, 1], (6, 1)))
    assert fixes.unreferenced_vertices == 2
    np.testing.assert_array_equal(v2, SQUARE_V[:4])
    np.testing.assert_array_equal(f2, SQUARE_F)
    assert n2.shape == (4, 3)


@pytest.mark.parametrize("bad", [[0.0, 0, 0], [np.nan, 0, 1], [np.inf, 0, 0]])
def test_zero_or_non_finite_normals_are_recomputed_from_the_faces(bad) -> None:
    # A tent: two faces meeting on the ridge 0-1; vertex 0's normal comes from both.
    v = np.array([[0, 0, 1], [1, 0, 1], [1, 1, 0], [0, -1, 0]], dtype=float)
    f = np.array([[0, 3, 1], [0, 1, 2]])
    given = np.array([bad, [0, 0, 1], [0, 0.6, 0.8], [0, -0.6, 0.8]], dtype=float)
    _, _, n, fixes = repair(v, f, given)
    assert fixes.normals_recomputed == 1
    assert "1 zero or non-finite normals recomputed" in fixes.summary()
    np.testing.assert_allclose(n[0], [0, 0, 1], atol=1e-12)  # the two slopes' mean: straight up
    np.testing.assert_allclose(n[1:], given[1:] / np.linalg.norm(given[1:], axis=1)[:, None])


def test_a_normal_whose_faces_cancel_takes_a_face_normal() -> None:
    # The square and its back face share vertices: the area-weighted sum at each vertex is zero.
    f = np.array([[0, 1, 2], [0, 2, 1]])
    given = np.zeros((3, 3))
    _, _, n, fixes = repair(SQUARE_V[:3], f, given)
    assert fixes.normals_recomputed == 3
    assert np.allclose(np.abs(n[:, 2]), 1.0)  # each is one face's normal, +z or -z


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_non_finite_coordinate_is_refused_with_its_index(value, tmp_path) -> None:
    v = SQUARE_V[:4].copy()
    v[2, 1] = value
    with pytest.raises(
        ValueError, match=r"vertex 2 = \[1\.0, (nan|inf|-inf), 0\.0\] is not finite"
    ):
        repair(v, SQUARE_F, None)
    path = _write_obj(tmp_path / "nan.obj", v, SQUARE_F)
    with pytest.raises(ValueError, match=rf"^{path}: vertex 2 = .* is not finite.*legal"):
        read_mesh(path)


def test_mesh_with_no_face_left_is_refused(tmp_path) -> None:
    path = _write_obj(tmp_path / "flat.obj", [[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]])
    with pytest.raises(ValueError, match=r"flat\.obj: no face is left.*1 degenerate faces"):
        read_mesh(path)


def test_a_file_with_every_defect_renders_with_a_summary(tmp_path) -> None:
    """The defects together, through a file (PLY keeps every vertex it lists): one line says
    what was repaired."""
    v = np.vstack([SQUARE_V, [[0.5, 0.5, 0]]])  # 4: unused; 5: the square's centre
    faces = [[0, 1, 5], [1, 2, 5], [2, 3, 5], [3, 0, 5], [1, 2, 5], [0, 0, 1], [0, 1, 2]]
    normals = np.tile([0.0, 0, 1], (6, 1))
    normals[5] = 0.0  # a zero normal on a used vertex
    path = tmp_path / "messy.ply"
    tm = trimesh.Trimesh(v, faces, vertex_normals=normals, process=False)
    tm.export(path, vertex_normal=True)
    loaded = read_mesh(path)
    assert loaded.summary() == (
        "messy.ply: 5 triangles, 5 vertices; 1 degenerate faces dropped; 1 duplicate faces "
        "dropped; 1 unreferenced vertices removed; 1 zero or non-finite normals recomputed; "
        "up +z (given)"
    )
    np.testing.assert_allclose(loaded.mesh.normals, np.tile([0, 0, 1.0], (5, 1)))
    sc = meshes.scene_from_mesh(loaded.mesh, width=16, height=16)
    assert sc.n_triangles == 5


def test_file_without_normals_gets_smooth_normals_split_at_creases(tmp_path) -> None:
    """An STL stores every corner apart: the corners are welded, then a box keeps its flat sides
    (split at its 90-degree edges) while a fine sphere stays smooth."""
    trimesh.creation.box([1, 1, 1]).export(tmp_path / "box.stl")
    box = read_mesh(tmp_path / "box.stl")
    assert box.repairs.normals_from == "computed" and box.repairs.welded_vertices == 36 - 8
    assert box.mesh.n_vertices == 24 and box.mesh.n_triangles == 12  # 4 corners per side
    face_n = np.cross(*np.swapaxes(np.diff(box.mesh.vertices[box.mesh.triangles], axis=1), 0, 1))
    face_n /= np.linalg.norm(face_n, axis=1, keepdims=True)
    for corner in range(3):  # every corner's normal is its face's: flat sides
        np.testing.assert_allclose(box.mesh.normals[box.mesh.triangles[:, corner]], face_n)
    trimesh.creation.icosphere(subdivisions=3).export(tmp_path / "ball.stl")
    ball = read_mesh(tmp_path / "ball.stl")
    assert ball.repairs.crease_splits == 0 and ball.mesh.n_vertices == 642
    np.testing.assert_allclose(  # smooth: each normal close to the radius through it
        np.einsum("ij,ij->i", ball.mesh.normals, ball.mesh.vertices), 1.0, atol=0.01
    )


# ------------------------------------------------------------------------------ formats
def _shape() -> trimesh.Trimesh:
    """A small, lopsided test shape (a capsule, stretched and shifted), no symmetry to hide a
    swapped axis."""
    tm = trimesh.creation.capsule(height=1.0, radius=0.4, count=[12, 8])
    tm.apply_scale([1.0, 0.7, 1.3])
    tm.apply_translation([0.3, -0.2, 0.5])
    return tm


@pytest.mark.parametrize("ext", FORMATS)
def test_every_format_reads_the_same_surface(ext: str, tmp_path) -> None:
    tm = _shape()
    path = tmp_path / f"shape.{ext}"
    tm.export(path)
    mesh = read_mesh(path, up="z").mesh  # z: the file's coordinates, whatever the format
    assert mesh.n_triangles == len(tm.faces)
    np.testing.assert_allclose(mesh.bounds()[0], tm.bounds[0], atol=1e-5)
    np.testing.assert_allclose(mesh.bounds()[1], tm.bounds[1], atol=1e-5)
    area = (
        np.linalg.norm(
            np.cross(*np.swapaxes(np.diff(mesh.vertices[mesh.triangles], axis=1), 0, 1)), axis=1
        ).sum()
        / 2
    )
    assert area == pytest.approx(tm.area, rel=1e-5)
    assert mesh.name == "shape"


def test_polygons_are_triangulated(tmp_path) -> None:
    obj = tmp_path / "quad.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    off = tmp_path / "quad.off"
    off.write_text("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
    for path in (obj, off):
        mesh = read_mesh(path).mesh
        assert mesh.n_triangles == 2 and np.allclose(mesh.normals, [0, 0, 1]), path


def test_a_file_of_several_meshes_is_one_mesh_with_node_transforms(tmp_path) -> None:
    a = trimesh.creation.box([1, 1, 1])
    b = trimesh.creation.icosphere(subdivisions=1)
    scene = trimesh.Scene()
    scene.add_geometry(a, node_name="a")
    scene.add_geometry(
        b, node_name="b", transform=trimesh.transformations.translation_matrix([3, 0, 0])
    )
    scene.export(tmp_path / "two.glb")
    mesh = read_mesh(tmp_path / "two.glb", up="z").mesh
    assert mesh.n_triangles == len(a.faces) + len(b.faces)
    assert mesh.bounds()[1][0] == pytest.approx(4.0)  # the sphere moved by its node


@pytest.mark.parametrize(
    ("name", "content", "why"),
    [
        ("missing.obj", None, "does not exist: legal value is an existing mesh file"),
        ("points.xyz", "0 0 0\n", "legal suffixes are .obj, .ply, .off, .stl, .glb, .gltf"),
        ("garbage.obj", "this is not a mesh\n", "holds no triangle mesh"),
        ("garbage.off", "OFF\n3 1\nnope\n", "could not be read as OFF"),
        ("binary.ply", b"\xff\xfe\x00\x81", "could not be read as PLY"),
        ("empty.stl", b"", "holds no triangle mesh"),
        ("junk.glb", b"glTF\x02\x00\x00\x00junk", "could not be read as GLB"),
    ],
)
def test_unreadable_file_is_refused_naming_it(name, content, why, tmp_path) -> None:
    path = tmp_path / name
    if isinstance(content, str):
        path.write_text(content)
    elif content is not None:
        path.write_bytes(content)
    with pytest.raises(ValueError) as err:
        read_mesh(path)
    message = str(err.value)
    assert str(path) in message and why in message and "\n" not in message, message


# ------------------------------------------------------------------------------ orientation
@pytest.mark.parametrize("axis", ["x", "y", "z", "-x", "-y", "-z"])
def test_up_rotation_is_proper_and_takes_the_axis_to_z(axis: str) -> None:
    r = up_rotation(axis)
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(r) == pytest.approx(1.0)
    vec = np.zeros(3)
    vec["xyz".index(axis[-1])] = -1.0 if axis.startswith("-") else 1.0
    np.testing.assert_allclose(r @ vec, [0, 0, 1])


def test_y_up_is_the_usual_turn_front_towards_the_camera() -> None:
    v, n = orient(np.array([[0.0, 1, 0], [0, 0, 1]]), np.array([[0.0, 0, 1], [1, 0, 0]]), "y")
    np.testing.assert_allclose(v, [[0, 0, 1], [0, -1, 0]])  # up to +z, the front +z to -y
    np.testing.assert_allclose(n, [[0, -1, 0], [1, 0, 0]])  # normals turn with the surface


def _standing_cone(up: str) -> trimesh.Trimesh:
    """A cone standing on its flat base along ``up`` (apex at +3 along it)."""
    cone = trimesh.creation.cone(radius=1.0, height=3.0, sections=24)  # base z = 0, apex z = 3
    to_axis = up_rotation(up).T  # from +z to the axis
    matrix = np.eye(4)
    matrix[:3, :3] = to_axis
    return cone.apply_transform(matrix)


@pytest.mark.parametrize("up", ["x", "y", "z", "-x", "-y", "-z"])
@pytest.mark.parametrize("ext", ["obj", "off", "stl", "ply"])
def test_named_and_auto_up_stand_a_mesh_upright(up: str, ext: str, tmp_path) -> None:
    path = tmp_path / f"cone.{ext}"
    _standing_cone(up).export(path)
    for given in (up, "auto"):
        loaded = read_mesh(path, up=given, normalise_size=True)
        v = loaded.mesh.vertices
        apex = v[np.argmax(v[:, 2])]
        assert loaded.up == up and np.allclose(apex[:2], 0, atol=1e-6), (given, apex)
        assert v[:, 2].max() == pytest.approx(1.0) and v[:, 2].min() == pytest.approx(-1.0)
        if given == "auto":
            assert "flat base" in loaded.up_reason


def test_auto_up_follows_gltf_and_falls_back_to_z(tmp_path) -> None:
    _standing_cone("y").export(tmp_path / "cone.glb")
    loaded = read_mesh(tmp_path / "cone.glb", up="auto")
    assert loaded.up == "y" and "glb is +y up by its specification" in loaded.up_reason
    box = trimesh.creation.box([1, 2, 3])  # flat every way: no clear base
    assert auto_up(box.vertices, box.faces, ".obj") == (
        "z",
        "auto: no convention and no clear flat base, so z",
    )
    ball = trimesh.creation.icosphere(2)
    assert auto_up(ball.vertices, ball.faces)[0] == "z"


def test_normalise_centres_and_scales_to_a_side_of_two(tmp_path) -> None:
    tm = _shape()
    tm.apply_scale(1000.0)
    tm.export(tmp_path / "big.ply")
    loaded = read_mesh(tmp_path / "big.ply", normalise_size=True)
    lo, hi = loaded.mesh.bounds()
    np.testing.assert_allclose((lo + hi) / 2, 0, atol=1e-12)
    assert (hi - lo).max() == pytest.approx(2.0)
    assert loaded.scale == pytest.approx(2.0 / tm.extents.max())


def test_up_is_checked() -> None:
    with pytest.raises(ValueError, match=r"up = 'w' is not legal: legal values are 'auto' \| 'x'"):
        read_mesh("any.obj", up="w")
    for a, b in itertools.combinations(meshfile.UP_AXES[1:], 2):
        assert not np.allclose(up_rotation(a), up_rotation(b))


def test_off_as_geomview_writes_it(tmp_path) -> None:
    """OFF with comments after the header and after vertices, polygons of mixed sizes with a
    colour after their corners (as geomview's own files are): read whole, fan-triangulated."""
    text = (
        "# a comment before the header\nOFF\n# and after it\n5 2 0\n"
        "0 0 0  # vertex 0\n1 0 0\n1 1 0\n0 1 0\n0.5 1.5 0\n"
        "4  0 1 2 3  0.8 0.1 0.1\n3  3 2 4  7\n"
    )
    path = tmp_path / "geomview.off"
    path.write_text(text)
    mesh = read_mesh(path).mesh
    assert (mesh.n_vertices, mesh.n_triangles) == (5, 3)
    np.testing.assert_allclose(mesh.normals, np.tile([0, 0, 1.0], (5, 1)))
    four_d = tmp_path / "hyper.off"
    four_d.write_text("4OFF\n4 1 0\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n3 0 1 2\n")
    with pytest.raises(ValueError, match=r"is a 4OFF file \(4-D or n-D vertices\): legal is a 3-D"):
        read_mesh(four_d)
