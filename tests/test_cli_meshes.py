# SPDX-License-Identifier: Apache-2.0
"""Your own mesh and scene file on the command line: ``demo --mesh FILE --up AXIS``
renders any format upright with every method and the NMSE table, a messy mesh with its repair
summary, ``demo --scene FILE`` reproduces a built-in scene byte for byte, and a bad scene file is
one line, exit 2, before any work."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
import trimesh

from model.render import meshfile, scenefile
from model.study.report import METHOD_LABELS
from tests.test_cli import run_cli


def _standing_cone_y() -> trimesh.Trimesh:
    """A cone standing on its base along +y (a y-up model): apex at y = 3."""
    cone = trimesh.creation.cone(radius=1.0, height=3.0, sections=16)
    matrix = np.eye(4)
    matrix[:3, :3] = meshfile.up_rotation("y").T  # +z to +y
    return cone.apply_transform(matrix)


@pytest.mark.parametrize("ext", ["off", "stl", "glb", "obj"])
def test_demo_renders_a_y_up_mesh_upright_in_every_format(ext: str, tmp_path, capsys) -> None:
    path = tmp_path / f"cone.{ext}"
    _standing_cone_y().export(path)
    out_dir = tmp_path / "out"
    argv = ["demo", "--mesh", str(path), "--up", "y", "--size", "24", "--out", str(out_dir)]
    status, out, err = run_cli(argv, capsys)
    assert status == 0, err
    lines = out.splitlines()
    assert lines[0] == f"== mesh {path}, 24 x 24: every method against (a) exact Blinn =="
    assert lines[1].startswith(f"cone.{ext}: 32 triangles") and lines[1].endswith("up +y (given)")
    for label in METHOD_LABELS.values():  # the NMSE table: a row per method
        assert any(line.startswith(f"| {label} |") for line in lines), label
    # Upright: the apex is the highest point of the mesh the demo drew, and at the top of the image.
    mesh = scenefile.mesh_source(path, "y").scene(24, 24).objects[0].mesh
    apex = mesh.vertices[np.argmax(mesh.vertices[:, 2])]
    assert np.allclose(apex[:2], 0, atol=1e-9) and apex[2] == pytest.approx(1.0)
    from PIL import Image

    image = np.asarray(Image.open(out_dir / "cone_exact.png"))
    rows = np.flatnonzero(image.any(axis=(1, 2)))
    cols_top = np.flatnonzero(image[rows[0]].any(axis=1))
    cols_bottom = np.flatnonzero(image[rows[-1]].any(axis=1))
    assert cols_top.size < cols_bottom.size  # narrow at the top (the apex), wide at the base
    # --up auto finds the same axis from the flat base (docs/meshes.md quotes this line)
    if ext != "glb":  # a GLB is +y up by its specification: auto says so
        assert (
            scenefile.mesh_source(path, "auto")
            .read()
            .summary()
            .endswith("up +y (auto: a flat base faces -y, covering 77 % of the footprint)")
        )


def test_messy_mesh_renders_with_a_repair_summary(tmp_path, capsys) -> None:
    tm = trimesh.creation.icosphere(subdivisions=1)
    faces = np.vstack(
        [tm.faces, tm.faces[:3], [[0, 0, 1], [2, 2, 2]]]
    )  # 3 duplicates, 2 degenerate
    path = tmp_path / "messy.ply"
    trimesh.Trimesh(tm.vertices, faces, process=False).export(path)
    status, out, err = run_cli(
        ["demo", "--mesh", str(path), "--size", "16", "--out", str(tmp_path / "o")], capsys
    )
    assert status == 0, err
    assert out.splitlines()[1].startswith(
        "messy.ply: 80 triangles, 42 vertices; 2 degenerate faces dropped; 3 duplicate faces "
        "dropped; normals computed"
    )


def test_demo_scene_file_reproduces_the_builtin_scene_byte_for_byte(tmp_path, capsys) -> None:
    copy = tmp_path / "my_sphere.toml"
    shutil.copy(scenefile.SCENE_DIR / "sphere.toml", copy)
    outs = {}
    for name, source in (("builtin", "sphere"), ("file", str(copy))):
        outs[name] = tmp_path / name
        argv = ["demo", "--scene", source, "--size", "32", "--out", str(outs[name])]
        status, _, err = run_cli(argv, capsys)
        assert status == 0, err
    images = sorted(p.name for p in outs["builtin"].glob("*.png"))
    assert len(images) >= 2 * len(METHOD_LABELS)
    assert images == sorted(p.name for p in outs["file"].glob("*.png"))
    for image in images:  # every method's image and heat-map, and the sheet
        same = (outs["builtin"] / image).read_bytes() == (outs["file"] / image).read_bytes()
        assert same, image


@pytest.mark.parametrize("command", ["demo", "bench", "trade"])
def test_bad_scene_file_is_one_line_before_any_work(command, tmp_path, capsys, monkeypatch):
    def started(*args, **kwargs):
        raise AssertionError("the work started")

    from model import cli
    from model.study import trade

    for target, name in ((cli, "demo"), (cli, "bench"), (trade, "main")):
        monkeypatch.setattr(target, name, started)
    bad = tmp_path / "bad.toml"
    bad.write_text('[[mesh]]\nshape = "sphere"\n[mesh.material]\nn = 5000\n')
    status, out, err = run_cli([command, "--scene", str(bad)], capsys)
    assert status == 2 and out == "" and "Traceback" not in err
    assert err.strip().splitlines()[-1] == (
        f"shading {command}: error: argument --scene{'s/--scene' if command == 'trade' else ''}: "
        f"{bad}: mesh[0].material.n = 5000 is out of range: legal range is 1..1000"
    )


def test_trade_takes_scene_files(tmp_path, capsys, monkeypatch) -> None:
    from model.study import trade

    calls: list[dict] = []
    monkeypatch.setattr(trade, "main", lambda **kwargs: calls.append(kwargs) or 0)
    scene = tmp_path / "s.toml"
    scene.write_text('[[mesh]]\nshape = "torus"\n')
    assert run_cli(["trade", "--scene", "sphere", str(scene), "--up", "y"], capsys)[0] == 0
    assert calls[0]["scenes"] == ["sphere", scenefile.SceneSource("file", str(scene))]
    assert calls[0]["up"] == "y"


def test_bench_load_times_every_format(capsys) -> None:
    """``bench-load`` (small here: the timing is a benchmark, not a test) reads every format and
    prints the table and the target's verdict."""
    status, out, err = run_cli(["bench-load", "--triangles", "500", "--repeats", "1"], capsys)
    assert status == 0, err
    for suffix in (".obj", ".ply", ".off", ".stl", ".glb"):
        assert any(line.startswith(f"| {suffix} | ") for line in out.splitlines()), suffix
    assert "target: every file under 2 s: slowest" in out
