# SPDX-License-Identifier: Apache-2.0
"""The command lines: ``shading <command>`` / ``python -m model <command>`` and
``python -m sim bench``.

Every command has its own ``--help`` with examples; ``--scene`` and ``--mesh`` exclude each
other; a mesh file renders like a built-in scene; a bad mesh file is one line, exit 2, before any
work.  The model's command line runs in-process (``model.cli.main``), ``python -m sim`` in a
subprocess started from another folder."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from model import cli
from model.cli import main

COMMANDS = [
    "demo",
    "bench",
    "bench-load",
    "trade",
    "accuracy",
    "roms",
    "divider-table",
    "divider-trade",
]


def run_cli(argv: list[str], capsys) -> tuple[int, str, str]:
    """(exit status, stdout, stderr) of ``shading <argv>``: argparse exits, commands return."""
    try:
        status = main(argv)
    except SystemExit as exc:
        status = exc.code
    out, err = capsys.readouterr()
    return status, out, err


def examples(help_text: str) -> list[str]:
    """The example command lines of a ``--help``: the lines after ``examples:``."""
    assert "examples:" in help_text, help_text
    lines = help_text.split("examples:", 1)[1].splitlines()
    return [x.strip() for x in lines if x.strip()]


@pytest.fixture
def no_work(monkeypatch):
    """Parsing only: a command that starts fails the test at once."""

    def started(*args, **kwargs):
        raise AssertionError("the work started")

    monkeypatch.setattr(cli, "demo", started)
    monkeypatch.setattr(cli, "bench", started)
    from model.study import trade

    monkeypatch.setattr(trade, "main", started)


@pytest.fixture(scope="module")
def ball(tmp_path_factory) -> Path:
    """A small mesh file: an icosphere (320 triangles) exported by trimesh as OBJ."""
    import trimesh

    path = tmp_path_factory.mktemp("mesh") / "ball.obj"
    trimesh.creation.icosphere(subdivisions=2).export(path)
    return path


@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_has_help_with_examples(command: str, capsys) -> None:
    status, out, err = run_cli([command, "--help"], capsys)
    assert status == 0 and err == ""
    assert out.startswith(f"usage: shading {command}")
    shown = examples(out)
    assert 2 <= len(shown) <= 3, shown
    assert all(x.startswith(("shading ", "python -m model ")) for x in shown), shown
    assert all(command in x for x in shown), shown


def test_top_help_lists_every_command(capsys) -> None:
    status, out, _ = run_cli(["--help"], capsys)
    assert status == 0
    listed = out.split("positional arguments:", 1)[1].split("options:", 1)[0]
    for command in COMMANDS:
        assert f"    {command}" in listed, command
    assert examples(out)
    # the installed console script and ``python -m model`` show the same
    script = Path(sys.executable).with_name("shading")
    for argv in ([str(script)], [sys.executable, "-m", "model"]):
        if argv[0] == str(script) and not script.exists():
            continue
        run = subprocess.run([*argv, "--help"], capture_output=True, text=True, timeout=60)
        assert run.returncode == 0 and run.stdout == out, run.stderr


def test_no_command_is_an_argument_error(capsys) -> None:
    status, out, err = run_cli([], capsys)
    assert status == 2 and out == ""
    assert "the following arguments are required: command" in err.strip().splitlines()[-1]


@pytest.mark.parametrize("command", ["demo", "bench"])
def test_scene_and_mesh_exclude_each_other(command: str, ball: Path, capsys, no_work) -> None:
    status, out, err = run_cli([command, "--scene", "sphere", "--mesh", str(ball)], capsys)
    assert status == 2 and out == ""
    assert "Traceback" not in err
    assert err.strip().splitlines()[-1] == (
        f"shading {command}: error: argument --mesh: not allowed with argument --scene"
    )


def test_demo_and_bench_render_a_mesh_file(ball: Path, tmp_path: Path, capsys) -> None:
    out_dir = tmp_path / "out"
    status, out, _ = run_cli(
        ["demo", "--mesh", str(ball), "--size", "32", "--out", str(out_dir)], capsys
    )
    assert status == 0
    assert out.startswith(f"== mesh {ball}, 32 x 32: every method against (a) exact Blinn ==")
    assert (out_dir / "ball_sheet.png").is_file() and (out_dir / "ball_exact.png").is_file()
    status, out, _ = run_cli(
        ["bench", "--mesh", str(ball), "--size", "16", "--repeats", "1"], capsys
    )
    assert status == 0
    assert out.startswith(f"== bench: mesh {ball} 16 x 16, best of 1 (shading only) ==")
    assert "target: (c) hybrid >= 10x (a) at 512 and 1024: not measured" in out


def test_bench_prints_one_table_for_scenes_and_sizes(capsys) -> None:
    """``bench --scenes --sizes``: one table, every scene at every size, each row's ratios,
    and every target stated (met, not met or not measured)."""
    status, out, _ = run_cli(
        ["bench", "--scenes", "sphere", "quad", "--sizes", "16", "24", "--repeats", "1"], capsys
    )
    assert status == 0
    assert out.startswith("== bench: sphere, quad 16 x 16, 24 x 24, best of 1 (shading only) ==")
    rows = [line for line in out.splitlines() if line.startswith("| ")][1:]
    labels = ("(a) exact Blinn", "(b) Phong", "numpy float Blinn", "(c) hybrid", "(g) adaptive")
    for scene in ("sphere", "quad"):
        for size in (16, 24):
            mine = [r for r in rows if r.startswith(f"| {scene} | {size} |")]
            assert all(any(f"| {label} |" in r for r in mine) for label in labels), mine
    assert "| (a) exact Blinn | " in out and "| 1.00x |" in out
    targets = [line for line in out.splitlines() if line.startswith("target: ")]
    assert len(targets) == 6
    assert all(t.endswith(("(met)", "(not met)")) or "not measured" in t for t in targets)
    assert "| (c) ceiling: its set-up's floor |" in out  # sizes 16 and 24: no ceiling line


def test_trade_takes_meshes_with_or_instead_of_scenes(ball: Path, capsys, monkeypatch) -> None:
    """``trade --mesh FILE`` (repeatable) reaches ``trade.main(meshes=[Path, ...])``; without
    ``--scenes`` only the meshes are swept, without ``--mesh`` every built-in scene."""
    from model.study import trade

    calls: list[dict] = []
    monkeypatch.setattr(trade, "main", lambda **kwargs: calls.append(kwargs) or 0)
    mesh = str(ball)
    assert run_cli(["trade", "--mesh", mesh, "--mesh", mesh], capsys)[0] == 0
    assert run_cli(["trade", "--scenes", "sphere", "--mesh", mesh], capsys)[0] == 0
    assert run_cli(["trade", "--size", "64"], capsys)[0] == 0
    only_meshes, both, neither = calls
    assert only_meshes["scenes"] == [] and only_meshes["meshes"] == [ball, ball]
    assert both["scenes"] == ["sphere"] and both["meshes"] == [ball]
    assert neither["scenes"] == list(cli.SCENES) and neither["meshes"] == []
    assert neither["size"] == 64 and neither["out_dir"] == Path("out/trade")


def _bad_meshes(tmp_path: Path) -> dict[str, tuple[Path, str]]:
    garbage = tmp_path / "garbage.obj"
    garbage.write_text("this is not\na mesh\n")
    binary = tmp_path / "binary.ply"
    binary.write_bytes(b"\xff\xfe\x00\x81")
    return {
        "missing": (tmp_path / "missing.obj", "does not exist: legal value is an existing"),
        "garbage": (garbage, "holds no triangle mesh: legal is a file with faces"),
        "binary": (binary, "could not be read as PLY"),
        "suffix": (tmp_path / "part.xyz", "legal suffixes are .obj, .ply, .off, .stl, .glb"),
    }


@pytest.mark.parametrize("kind", ["missing", "garbage", "binary", "suffix"])
@pytest.mark.parametrize("command", ["demo", "bench", "trade"])
def test_bad_mesh_file_is_one_line_before_any_work(
    command: str, kind: str, tmp_path: Path, capsys, no_work
) -> None:
    path, why = _bad_meshes(tmp_path)[kind]
    status, out, err = run_cli([command, "--mesh", str(path)], capsys)
    assert status == 2 and out == ""
    assert "Traceback" not in err
    line = err.strip().splitlines()[-1]
    assert line.startswith(f"shading {command}: error: argument --mesh: path = '{path}' ")
    assert why in line, line


def test_sim_command_line_from_another_folder(ball: Path, tmp_path: Path) -> None:
    """``python -m sim`` works from any folder: its help, and a bad mesh refused in one line
    (exit 2) before the co-simulation starts."""

    def sim(*argv: str) -> subprocess.CompletedProcess:
        return subprocess.run(
            [sys.executable, "-m", "sim", *argv],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=60,
        )

    top = sim("--help")
    assert top.returncode == 0, top.stderr
    assert "bench" in top.stdout.split("positional arguments:", 1)[1]
    bench = sim("bench", "--help")
    assert bench.returncode == 0 and bench.stdout.startswith("usage: python -m sim bench")
    shown = examples(bench.stdout)
    assert 2 <= len(shown) <= 3 and all(x.startswith("python -m sim bench") for x in shown)
    for argv, expect in [
        (["--mesh", "missing.obj"], "argument --mesh: path = 'missing.obj' does not exist"),
        (["--scene", "sphere", "--mesh", str(ball)], "argument --mesh: not allowed with"),
        (["--size", "4"], "argument --size: 4 is not allowed: must be an integer in 8..4096"),
        (["--vector-cycles", "5"], "argument --vector-cycles: 5 is not allowed: must be an"),
        (["--no-vectors", "--vectors-only"], "argument --vectors-only: not allowed with"),
        (["--core-only", "--no-core"], "argument --core-only: not allowed with --vectors-only"),
    ]:
        run = sim("bench", *argv)
        assert run.returncode == 2 and run.stdout == "" and "Traceback" not in run.stderr
        line = run.stderr.strip().splitlines()[-1]
        assert line.startswith("python -m sim bench: error: ") and expect in line, line
    assert not (tmp_path / "sim_build").exists()  # nothing started
