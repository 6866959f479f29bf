# SPDX-License-Identifier: Apache-2.0
"""Bad input at the command line and in the study: one test per row.

Every bad input gets one clear message naming the argument, its value and what is allowed; no
traceback, no hang, no work lost.  The command line is run in-process (``model.cli.main``)."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import socket
import subprocess
import sys

import numpy as np
import pytest

from model import cli
from model.cli import main
from model.render import meshes, raster, scene
from model.study import trade
from model.units import divider, specular
from sim.runner import env_seed

ROOT = meshes.REPO_ROOT
RUN_SWEEP = trade.run_sweep


@pytest.fixture
def no_work(monkeypatch):
    """A refusal must come before any work: a sweep or a demo that starts fails the test at once
    (instead of running for minutes)."""

    def started(*args, **kwargs):
        raise AssertionError("the work started")

    monkeypatch.setattr(trade, "run_sweep", started)
    monkeypatch.setattr(cli, "demo", started)
    monkeypatch.setattr(cli, "bench", started)


def run_cli(argv: list[str], capsys) -> tuple[int, str, str]:
    """(exit status, stdout, stderr) of ``shading <argv>``: argparse errors exit, the others
    return their status."""
    try:
        status = main(argv)
    except SystemExit as exc:
        status = exc.code
    out, err = capsys.readouterr()
    return status, out, err


def assert_one_line_error(err: str, *parts: str) -> str:
    """The last stderr line is the error and names every part; no traceback anywhere."""
    assert "Traceback" not in err
    line = err.strip().splitlines()[-1]
    assert "error:" in line
    for part in parts:
        assert part in line, (part, line)
    return line


# ---------------------------------------------------------------------- command-line arguments
def test_negative_workers_is_refused_not_hung(capsys, no_work) -> None:
    """``trade --workers -3`` hung (a LocalCluster of -3 workers): argparse refuses it now, and
    the Python API refuses it too."""
    status, out, err = run_cli(["trade", "--workers", "-3"], capsys)
    assert status == 2 and out == ""
    assert_one_line_error(err, "argument --workers: -3 is not allowed: must be an integer >= 1")
    with pytest.raises(ValueError, match=r"workers = -3 is out of range: legal is .* >= 0"):
        RUN_SWEEP([], "unused-cache", workers=-3)
    with pytest.raises(ValueError, match=r"workers = 0 is out of range: legal is .* >= 1"):
        trade.make_client(workers=0)


@pytest.mark.parametrize(
    ("argv", "expect"),
    [
        (
            ["trade", "--workers", "0"],
            "argument --workers: 0 is not allowed: must be an integer >= 1",
        ),
        (
            ["bench", "--repeats", "-1"],
            "argument --repeats: -1 is not allowed: must be an integer >= 1",
        ),
        (
            ["bench", "--repeats", "0"],
            "argument --repeats: 0 is not allowed: must be an integer >= 1",
        ),
        (
            ["trade", "--workers", "two"],
            "argument --workers: 'two' is not allowed: must be an integer",
        ),
        (
            ["demo", "--size", "4"],
            "argument --size: 4 is not allowed: must be an integer in 8..4096",
        ),
        (
            ["trade", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"],
            "argument --scheduler: not allowed with argument --workers",
        ),
    ],
)
def test_zero_workers_and_negative_repeats_are_refused(argv, expect, capsys, no_work) -> None:
    """``--workers 0`` and ``bench --repeats -1`` were silently accepted."""
    status, out, err = run_cli(argv, capsys)
    assert status == 2 and out == ""
    assert err.startswith("usage: shading")
    assert_one_line_error(err, expect)


@pytest.fixture
def a_file(tmp_path):
    f = tmp_path / "a-file"
    f.write_text("not a folder")
    return f


@pytest.mark.parametrize(
    ("command", "option", "under_file"),
    [("trade", "--out", True), ("trade", "--figure", False), ("demo", "--out", False)],
)
def test_unwritable_out_or_figure_is_refused_before_any_work(
    command, option, under_file, a_file, tmp_path, capsys, no_work
) -> None:
    """An unwritable ``--out`` / ``--figure`` gave a traceback after all the work: it is checked
    first now (a folder under a file cannot be made, even by root)."""
    bad = a_file / "sub" if under_file else a_file
    argv = [command, option, str(bad), "--scene" if command == "demo" else "--scenes", "sphere"]
    if option != "--out":
        argv += ["--out", str(tmp_path / "out")]
    status, out, err = run_cli(argv, capsys)
    assert status == 2
    assert out == ""  # nothing started: no header, no sweep
    why = "Not a directory" if under_file else "it is a file, not a folder"
    assert_one_line_error(
        err,
        f"shading {command}: error: argument {option}: '{bad}' is not allowed: {why}",
        "must be a folder this user can create and write in",
    )
    assert not list(tmp_path.rglob("*.json")) and not list(tmp_path.rglob("*.png"))


def _closed_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]  # closed again when the with-block ends


def test_unreachable_scheduler_fails_fast_naming_the_address(tmp_path, capsys, no_work) -> None:
    """An unreachable ``--scheduler`` waited 30 s, then an OSError traceback: now 5 s, one line."""
    address = f"tcp://127.0.0.1:{_closed_port()}"
    out_dir = tmp_path / "out"
    status, out, err = run_cli(
        ["trade", "--scheduler", address, "--scenes", "sphere", "--out", str(out_dir)], capsys
    )
    assert status == 1 and out == ""
    assert_one_line_error(
        err,
        f"shading trade: error: argument --scheduler: cannot connect to '{address}' "
        f"(no answer within {trade.CONNECT_TIMEOUT:g} s)",
        "must be the address of a running Dask scheduler",
    )
    assert not list(out_dir.rglob("*.json"))
    # not even an address: at once
    with pytest.raises(trade.SetupError, match=r"cannot connect to 'no:::address' \(invalid"):
        trade.connect("no:::address")


# ---------------------------------------------------------------------- the trade cache
def valid_result(p: trade.TradePoint, **figures) -> dict:
    """A result of ``p`` that ``trade.check_result`` accepts (every figure 1), then ``figures``."""
    result = {
        **dataclasses.asdict(p),
        "key": p.key,
        "config_key": p.config_key,
        "label": p.label,
        **{f: 1 if kind == "int" else 1.0 for f, (kind, *_) in trade.RESULT_RANGES.items()},
    }
    return {**result, **figures}


POINTS = [
    trade.TradePoint(scene="sphere", size=16),
    trade.TradePoint(scene="sphere", size=16, recip_bits=14),
]


def _sweep_with_fake_evaluate(cache, capsys):
    calls: list[str] = []

    def fake_evaluate(p, repeats):
        calls.append(p.key)
        return valid_result(p, nmse=0.25)

    outcome = trade.run_sweep(POINTS, cache, workers=0, evaluate_fn=fake_evaluate)
    return outcome, calls, capsys.readouterr()


def _payload(p, result) -> dict:
    return {"version": trade.CACHE_VERSION, "point": dataclasses.asdict(p), "result": result}


@pytest.mark.parametrize(
    ("content", "why"),
    [
        ("[1, 2]", "holds a JSON list, not an object"),
        ('{"version": ', "not valid JSON"),
        ("missing-field", "field 'cycles' is missing"),
        ("missing-result", "field 'result' is missing"),
        ("result-list", "result is a list, not an object"),
        ("wrong-type", "table_bits = 'many' is not legal: legal is an integer >= 0"),
    ],
)
def test_corrupt_cache_entry_is_recomputed_and_said_so(content, why, tmp_path, capsys) -> None:
    """A cache entry ``[1,2]`` or with a missing field aborted the sweep: now that entry is
    evaluated again with one line naming the file and why; the good entry is kept."""
    good, bad = POINTS
    trade.store(tmp_path, good, valid_result(good, nmse=0.5))
    if content == "missing-field":
        r = valid_result(bad)
        del r["cycles"]
        content = json.dumps(_payload(bad, r))
    elif content == "missing-result":
        content = json.dumps({k: v for k, v in _payload(bad, {}).items() if k != "result"})
    elif content == "result-list":
        content = json.dumps(_payload(bad, [1, 2]))
    elif content == "wrong-type":
        content = json.dumps(_payload(bad, valid_result(bad, table_bits="many")))
    trade.cache_path(tmp_path, bad).write_text(content)

    outcome, calls, captured = _sweep_with_fake_evaluate(tmp_path, capsys)
    assert calls == [bad.key]  # only the broken one: no work lost
    assert (outcome.cached, outcome.evaluated, outcome.failed) == (1, 1, {})
    assert list(outcome.recomputed) == [bad.key] and why in outcome.recomputed[bad.key]
    assert [r["nmse"] for r in outcome.results] == [0.5, 0.25]
    line = next(x for x in captured.out.splitlines() if "is not used" in x)
    assert str(trade.cache_path(tmp_path, bad)) in line and why in line
    assert "evaluating the point again" in line and "Traceback" not in captured.err
    # and the entry is repaired: the next run takes both from the cache
    again, calls, _ = _sweep_with_fake_evaluate(tmp_path, capsys)
    assert (again.cached, calls, again.recomputed) == (2, [], {})


@pytest.mark.parametrize(
    ("figure", "value", "why"),
    [
        ("nmse", -5, "nmse = -5 is out of range: legal is a finite number >= 0"),
        ("nmse", math.nan, "nmse = nan is out of range"),
        ("nmse", math.inf, "nmse = inf is out of range"),
        (
            "max_abs_error",
            300.0,
            "max_abs_error = 300.0 is out of range: legal is a finite number in 0..255",
        ),
        ("cycles", -1, "cycles = -1 is out of range: legal is an integer >= 0"),
        ("scene", "quad", "scene = 'quad' is not this point's 'sphere'"),
    ],
)
def test_edited_cache_figure_is_validated_not_copied_into_the_csv(
    figure, value, why, tmp_path, capsys
) -> None:
    """A cache nmse edited to -5 was copied into the CSV: the entry is refused and recomputed."""
    good, bad = POINTS
    trade.store(tmp_path, good, valid_result(good, nmse=0.5))
    trade.store(tmp_path, bad, valid_result(bad, **{figure: value}))
    outcome, calls, captured = _sweep_with_fake_evaluate(tmp_path, capsys)
    assert calls == [bad.key] and why in outcome.recomputed[bad.key]
    assert why in captured.out
    csv_path = trade.write_csv(outcome.results, tmp_path / "results.csv")
    rows = csv_path.read_text().splitlines()
    col = rows[0].split(",").index("nmse")
    assert [float(r.split(",")[col]) for r in rows[1:]] == [0.5, 0.25]
    # valid NaN figures (no specular unit) and an infinite PSNR (equal images) are accepted
    ok = valid_result(bad, psnr=math.inf, epicentre_rel_error=math.nan, angle_drift_steps=math.nan)
    assert trade.check_result(bad, ok) is None


def test_second_sweep_on_the_same_out_is_refused_naming_lock_and_pid(
    tmp_path, capsys, no_work
) -> None:
    """Two sweeps on the same ``--out`` did the work twice: the second is refused at once."""
    out_dir = tmp_path / "out"
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys, time\n"
            "from model.study import trade\n"
            "lock = trade.sweep_lock(sys.argv[1])\n"
            "lock.__enter__()\n"
            "print('held', flush=True)\n"
            "time.sleep(60)\n",
            str(out_dir / "cache"),
        ],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout.readline().strip() == "held"
        status, out, err = run_cli(
            ["trade", "--out", str(out_dir), "--scenes", "sphere", "--size", "16"], capsys
        )
        lock = out_dir / "cache" / trade.LOCK_NAME
        assert status == 1 and out == ""
        assert_one_line_error(
            err,
            f"another trade sweep (pid {holder.pid}) holds the lock {lock}",
            "one sweep at a time per --out",
        )
        with pytest.raises(trade.SetupError, match=f"pid {holder.pid}"):
            RUN_SWEEP([], out_dir / "cache", workers=0, progress=False)
    finally:
        holder.kill()
        holder.wait()
    # released with its process: the next sweep runs
    assert RUN_SWEEP([], out_dir / "cache", workers=0, progress=False).evaluated == 0


# ---------------------------------------------------------------------- geometry
def _one_triangle_scene(size: float) -> scene.Scene:
    v = np.array([[-size, -size, 0], [size, -size, 0], [0, size, 0]], dtype=np.float64)
    mesh = scene.Mesh(v, [[0, 1, 2]], np.tile([0, 0, 1.0], (3, 1)), name="huge")
    cam = scene.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), width=32, height=32)
    return scene.Scene((scene.SceneObject(mesh, scene.Material()),), cam)


def test_huge_triangle_is_refused_not_silently_empty() -> None:
    """A 1e18-unit triangle drew 0 pixels (the pixel indices overflowed int64): refused with the
    triangle, the vertex and the legal range; a 1e9-unit one still covers the whole image."""
    r = raster.rasterise(_one_triangle_scene(1e9))
    assert int((r.winner >= 0).sum()) == 32 * 32
    legal = "is out of range: legal screen coordinates are |x|, |y| <= 2**40"
    with pytest.raises(ValueError) as exc:
        raster.rasterise(_one_triangle_scene(1e18))
    msg = str(exc.value)
    assert msg.startswith("object 0 ('huge'), triangle 0, vertex 0 = (-1e+18, -1e+18, 0)")
    assert "projects to (-" in msg and legal in msg
    with pytest.raises(ValueError, match=r"screen_xy\[0, 1\] = \(1e\+18, -5\) " + legal[:20]):
        raster.screen_spans(np.array([[[0, 0], [1e18, -5], [0, 30]]]), 8, 8)
    _, _, xs, xe = raster.screen_spans(np.array([[[-1e9, -1e9], [1e9, -1e9], [0, 1e9]]]), 8, 8)
    assert int((xe - xs + 1).sum()) == 64


# ---------------------------------------------------------------------- the Python API
@pytest.mark.parametrize(
    ("make", "expect"),
    [
        (
            lambda: specular.SpecularConfig(a_frac_bits=1),
            "a_int_bits = 3 is out of range: the largest a = 7.9057 rounds to 8 at "
            "a_frac_bits = 1 (the ROM 9 word), which needs 4 integer bits: legal is "
            "a_int_bits >= 4 with a_frac_bits = 1, or a_frac_bits >= 3 with a_int_bits = 3",
        ),
        (
            lambda: divider.divide(2**70, 3),
            f"a = {2**70} is out of range: legal range is -1048576..1048575",
        ),
        (
            lambda: divider.divide([1, -(2**70)], 3),
            f"a = {-(2**70)} is out of range: legal range is -1048576..1048575",
        ),
        (
            lambda: divider.divide(1e30, 3),
            "a = 1e+30 is out of range: legal range is -1048576..1048575",
        ),
        (
            lambda: specular.setup_line([0, 0, 0], [0, 0, 1], [0, 0, 1], [0, 0, 1], 8, 1.0, 4),
            "n1 = [0, 0, 0] is out of range: legal is a non-zero 3-vector (length >= 1e-12)",
        ),
    ],
)
def test_api_messages_name_the_field_the_value_and_the_range(make, expect) -> None:
    """``SpecularConfig(a_frac_bits=1)`` said "a_int_bits = 3 ... needs 3 integer bits" (it
    forgot the rounding); ``divide(2**70, 3)`` said "a must be an integer"."""
    with pytest.raises(ValueError) as exc:
        make()
    assert str(exc.value) == expect


def test_huge_normal_is_normalised_like_any_other() -> None:
    """A normal (0, 0, 1e300) overflowed the length: setup_line said "n1[0] = [0, 0, 0] ... legal
    is non-zero", a Light silently lost its direction, a Mesh refused it as not finite."""
    huge = specular.setup_line([0, 0, 1e300], [0, 1e300, 1e300], [0, 0, 1], [0, 0, 1], 8, 1.0, 4)
    unit = specular.setup_line([0, 0, 1], [0, 1, 1], [0, 0, 1], [0, 0, 1], 8, 1.0, 4)
    assert huge == unit
    rows = specular.setup_lines([[1e300, 0, 0]], [[1, 0, 0]], [[1, 0, 0]], [[1, 0, 0]], 8, 1.0, 4)
    assert rows.c_reg[0] == unit.c_reg
    assert scene.Light(direction=(0, 0, 1e300)).direction == (0.0, 0.0, 1.0)
    mesh = scene.Mesh(np.eye(3), [[0, 1, 2]], [[0, 0, 1e300], [1e308, 1e308, 0], [0, 0, 2]])
    np.testing.assert_allclose(mesh.normals[1], [2**-0.5, 2**-0.5, 0])
    assert mesh.normals[0].tolist() == [0, 0, 1]


@pytest.fixture(scope="module")
def teapot_lines(teapot_file) -> list[str]:
    return teapot_file.read_text().splitlines()


@pytest.mark.parametrize(
    ("edit", "expect"),
    [
        (lambda ls: [*ls[:5], "0.8 abc 0.9", *ls[6:]], "line 6: '0.8 abc 0.9' is not legal"),
        (lambda ls: [*ls[:5], "0.8 0.9", *ls[6:]], "line 6: '0.8 0.9' is not legal"),
        (lambda ls: [*ls[:5], "0.8 nan 0.9", *ls[6:]], "line 6: '0.8 nan 0.9' is not legal"),
        (lambda ls: ["BPP", *ls[1:]], "line 1: 'BPP' is not legal: expected 'BBP'"),
        (lambda ls: ls[:-2], "expected a multiple of 48 (16 points x 3 per patch); the last "),
        (lambda ls: ["BBP"], "line 1: 'BBP' and no control point after it"),
    ],
)
def test_bad_teapot_file_names_the_file_and_the_line(edit, expect, teapot_lines, tmp_path) -> None:
    """A broken teapot file said "could not convert string to float: 'abc'" (no file name, no
    line): now the file, the line and what was expected there."""
    bad = tmp_path / "teapot.bez"
    bad.write_text("\n".join(edit(teapot_lines)) + "\n")
    with pytest.raises(ValueError) as exc:
        meshes.teapot_mesh(path=bad)
    msg = str(exc.value)
    assert msg.startswith(str(bad)) and expect in msg
    if "is not legal: expected three" in msg or "line 6" in msg:
        assert "expected three finite numbers 'x y z'" in msg
    binary = tmp_path / "binary.bez"
    binary.write_bytes(b"\xff\xfe\x00\x81")
    with pytest.raises(ValueError, match=r"binary\.bez: cannot be read as a text file"):
        meshes.read_bezier_patches(binary)


@pytest.mark.parametrize("variable", ["BENCH_SEED", "SOAK_SEED"])
def test_bad_seed_variable_is_one_clear_error(variable: str) -> None:
    """A non-integer seed stops pytest once, in one line naming the variable and its value,
    before any test runs (not one traceback per bench); an integer seed is taken as given."""
    env = {**os.environ, variable: "abc"}
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "tests/test_divider.py"],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    output = run.stdout + run.stderr
    assert run.returncode != 0 and "Traceback" not in output, output
    assert f"{variable}='abc' is not allowed: it must be an integer seed" in output, output
    assert output.count("is not allowed") == 1, output

    os.environ[variable] = "0x10"
    try:
        assert env_seed(variable) == 16
    finally:
        del os.environ[variable]
