# SPDX-License-Identifier: Apache-2.0
"""Scene files: the built-in scenes are files, every field is checked, transforms and framing.

A bad field is refused with one message naming the file, the field, its value and what is
allowed; the table below holds one case per check.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
import trimesh

from model.render import meshes, scenefile
from model.render.scene import Scene
from model.render.scenefile import SCENE_DIR, SCENE_NAMES, SceneSource, read_scene

MINIMAL = '[[mesh]]\nshape = "sphere"\nsubdivisions = 1\n'


def _write(tmp_path: Path, text: str, name: str = "sc.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _same_scene(a: Scene, b: Scene) -> None:
    assert (a.name, a.viewer, a.background, a.camera, a.light) == (
        b.name,
        b.viewer,
        b.background,
        b.camera,
        b.light,
    )
    assert len(a.objects) == len(b.objects)
    for x, y in zip(a.objects, b.objects, strict=True):
        assert x.material == y.material
        for field in ("vertices", "triangles", "normals"):
            np.testing.assert_array_equal(getattr(x.mesh, field), getattr(y.mesh, field))


@pytest.mark.parametrize("name", SCENE_NAMES)
def test_each_builtin_scene_is_its_shipped_file(teapot_file, name: str, tmp_path) -> None:
    """A copy of the shipped file, anywhere, is the built-in scene (the examples are real)."""
    copy = tmp_path / f"my_{name}.toml"
    shutil.copy(SCENE_DIR / f"{name}.toml", copy)
    _same_scene(read_scene(copy, 40, 30), scenefile.builtin_scene(name, 40, 30))
    assert read_scene(copy, 40, 30).camera.width == 40


def test_builtin_scenes_match_their_description() -> None:
    """What the docstrings and docs/scenes.md say of each scene, from the files."""
    want = {
        "sphere": (1280, 60, "directional", "infinite"),
        "torus": (48 * 24 * 2, 20, "point", "local"),
        "quad": (32 * 32 * 2, 1000, "point", "local"),
    }
    for name, (tris, n, light, viewer) in want.items():
        sc = scenefile.builtin_scene(name, 16, 16)
        assert (sc.n_triangles, sc.n_values, sc.light.kind, sc.viewer) == (
            tris,
            (n,),
            light,
            viewer,
        )


def test_minimal_file_takes_the_defaults(tmp_path) -> None:
    sc = read_scene(_write(tmp_path, MINIMAL), 32, 24)
    assert sc.name == "sc" and sc.viewer == "infinite" and sc.background == (0, 0, 0)
    assert sc.light.kind == "directional" and sc.objects[0].material == scenefile.Material()
    # The framed camera of meshes.scene_from_mesh: the same eye for the same mesh.
    framed = meshes.scene_from_mesh(meshes.sphere_mesh(1.0, 1), width=32, height=24)
    assert sc.camera == framed.camera and sc.light == framed.light


def test_transforms_scale_rotate_translate(tmp_path) -> None:
    text = (
        '[[mesh]]\nshape = "quad"\nsize = 2.0\nbulge = 0.0\ncells = 1\n'
        "scale = 3.0\nrotate = [90.0, 0.0, 0.0]\ntranslate = [1.0, 2.0, 3.0]\n"
    )
    mesh = read_scene(_write(tmp_path, text), 16, 16).objects[0].mesh
    flat = meshes.domed_quad_mesh(2.0, 0.0, 1)
    # 90 degrees about x takes (x, y, z) to (x, -z, y): the quad stands in the xz plane.
    expect = flat.vertices[:, [0, 2, 1]] * [3, -3, 3] + [1, 2, 3]
    np.testing.assert_allclose(mesh.vertices, expect, atol=1e-12)
    np.testing.assert_allclose(mesh.normals, np.tile([0, -1.0, 0], (4, 1)), atol=1e-12)


def test_mesh_files_are_relative_to_the_scene_file_and_framed_together(tmp_path) -> None:
    folder = tmp_path / "models"
    folder.mkdir()
    trimesh.creation.icosphere(subdivisions=1).export(folder / "ball.ply")
    trimesh.creation.box([1, 1, 1]).export(folder / "box.off")
    text = (
        '[[mesh]]\nfile = "models/ball.ply"\nup = "z"\n'
        '[[mesh]]\nfile = "models/box.off"\nnormalise = false\ntranslate = [4.0, 0.0, 0.0]\n'
        "[mesh.material]\nn = 300\ncolour = [0.1, 0.2, 0.3]\n"
    )
    path = _write(tmp_path, text)
    sc = read_scene(path, 48, 48)
    assert sc.n_triangles == 80 + 12 and sc.n_values == (50, 300)
    assert sc.objects[1].mesh.bounds()[1][0] == pytest.approx(4.5)
    assert scenefile.mesh_files(path) == [folder / "ball.ply", folder / "box.off"]
    from model.render import raster

    winner = raster.rasterise(sc).winner  # global triangle ids: both meshes are in the picture
    assert (winner[winner >= 0] < 80).any() and (winner >= 80).any()


def test_scene_key_follows_every_file(tmp_path) -> None:
    trimesh.creation.icosphere(subdivisions=1).export(tmp_path / "ball.ply")
    path = _write(tmp_path, '[[mesh]]\nfile = "ball.ply"\n')
    source = SceneSource("file", str(path))
    key = source.key()
    assert key.startswith("scene:sc.toml@") and len(key) == len("scene:sc.toml@") + 12
    trimesh.creation.icosphere(subdivisions=2).export(tmp_path / "ball.ply")
    assert source.key() != key  # the mesh it names changed


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "mesh = None is not legal: legal is one or more [[mesh]] tables"),
        ("name = 3\n" + MINIMAL, "name = 3 is not legal: legal is a non-empty string"),
        ("colour = 1\n" + MINIMAL, "colour is not a field here: legal fields are name, viewer"),
        ('viewer = "near"\n' + MINIMAL, "viewer = 'near' is not legal: legal values are"),
        ("background = [0, 0, 300]\n" + MINIMAL, "background[2] = 300 is out of range"),
        ("background = [0, 0]\n" + MINIMAL, "background = [0, 0] is not legal: legal is [r, g, b]"),
        ("[camera]\nfov_y = 500\n" + MINIMAL, "camera.eye is missing: legal is eye, target"),
        (
            "[camera]\neye = [0, -4, 1]\ntarget = [0, 0, 0]\nfov_y = 500\n" + MINIMAL,
            "camera.fov_y = 500 is out of range: legal range is 1.0..170.0",
        ),
        (
            "[camera]\neye = [0, 0, 0]\ntarget = [0, 0, 0]\n" + MINIMAL,
            "camera.target - eye = (0.0, 0.0, 0.0) cannot be normalised",
        ),
        ("[camera]\neye = [0, 1]\ntarget = [0, 0, 0]\n" + MINIMAL, "camera.eye = [0, 1] is not"),
        ('[camera]\neye = "here"\n' + MINIMAL, "camera.eye = 'here' is not legal: legal is a list"),
        ("[camera]\neyes = [0, 1, 2]\n" + MINIMAL, "camera.eyes is not a field here"),
        ("[camera]\nframe = true\neye = [0, 1, 2]\n" + MINIMAL, "camera.eye is not legal with"),
        ("[camera]\nframe = 1\n" + MINIMAL, "camera.frame = 1 is not legal: legal is true or"),
        ("[camera]\nframe = true\nfill = 2.0\n" + MINIMAL, "camera.fill = 2 is out of range"),
        ("[camera]\ndirection = [0, 1, 0]\n" + MINIMAL, "camera.direction is not legal without"),
        (
            "[camera]\nframe = true\ndirection = [0, 0, 0]\n" + MINIMAL,
            "camera.direction = (0.0, 0.0, 0.0) cannot be normalised",
        ),
        ('[light]\nkind = "spot"\n' + MINIMAL, "light.kind = 'spot' is not legal: legal values"),
        ("[light]\nintensity = 17\n" + MINIMAL, "light.intensity = 17 is out of range"),
        ('[light]\nintensity = "max"\n' + MINIMAL, "light.intensity = 'max' is not legal: legal"),
        (
            '[[light]]\nkind = "point"\n[[light]]\nkind = "point"\n' + MINIMAL,
            "light has 2 entries: legal is one light",
        ),
        ("[[mesh]]\nscale = 2.0\n", "mesh[0] has neither file and shape: legal is one of them"),
        (
            '[[mesh]]\nshape = "sphere"\nfile = "a.obj"\n',
            "mesh[0] has both file and shape: legal is one of them",
        ),
        ('[[mesh]]\nshape = "cube"\n', "mesh[0].shape = 'cube' is not legal: legal values are"),
        ('[[mesh]]\nshape = "sphere"\nradius = -1.0\n', "mesh[0].radius = -1 is out of range"),
        ('[[mesh]]\nshape = "sphere"\nsteps = 3\n', "mesh[0].steps is not a field here"),
        ('[[mesh]]\nshape = "sphere"\nradius = "big"\n', "mesh[0].radius = 'big' is not legal"),
        ('[[mesh]]\nshape = "sphere"\nup = "y"\n', "mesh[0].up is not a field here"),
        ('[[mesh]]\nfile = "none.obj"\n', "mesh[0].path = "),
        ('[[mesh]]\nfile = "none.obj"\nup = "w"\n', "mesh[0].up = 'w' is not legal"),
        ('[[mesh]]\nfile = "a.obj"\nnormalise = "yes"\n', "mesh[0].normalise = 'yes' is not"),
        ("[[mesh]]\nfile = 3\n", "mesh[0].file = 3 is not legal: legal is a path"),
        (MINIMAL + "scale = 0.0\n", "mesh[0].scale = 0 is out of range"),
        (MINIMAL + "rotate = [1.0, 2.0]\n", "mesh[0].rotate = [1.0, 2.0] is not legal"),
        (MINIMAL + "[mesh.material]\nn = 0\n", "mesh[0].material.n = 0 is out of range: legal"),
        (MINIMAL + "[mesh.material]\nk_s = 2\n", "mesh[0].material.k_s = 2 is out of range"),
        (MINIMAL + "[mesh.material]\nshine = 2\n", "mesh[0].material.shine is not a field"),
        (MINIMAL + '[mesh.material]\nn = "high"\n', "mesh[0].material.n = 'high' is not legal"),
        (
            MINIMAL + "[mesh.material]\ncolour = [1, 0, 2]\n",
            "mesh[0].material.colour[2] = 2 is out of range",
        ),
        ("[[mesh]\n", "not valid TOML"),
    ],
)
def test_every_field_is_checked(text: str, message: str, tmp_path) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(ValueError) as err:
        read_scene(path, 16, 16)
    said = str(err.value)
    assert said.startswith(f"{path}: ") and message in said, said
    assert "legal" in said or "not valid TOML" in said, said


def test_scene_source_names(tmp_path) -> None:
    assert scenefile.scene_source("torus") == SceneSource("builtin", "torus")
    path = _write(tmp_path, MINIMAL)
    assert scenefile.scene_source(str(path)) == SceneSource("file", str(path))
    with pytest.raises(ValueError, match=r"scene = 'cube' is not legal: legal is a built-in"):
        scenefile.scene_source("cube")
    with pytest.raises(ValueError, match=r"does not exist: legal value is an existing \.toml"):
        scenefile.scene_source(str(tmp_path / "none.toml"))
