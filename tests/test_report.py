# SPDX-License-Identifier: Apache-2.0
"""The method comparison behind `make demo` and `make bench`, on a small scene."""

from __future__ import annotations

import pytest

from model.cli import main
from model.study import report
from model.units import divider, specular


@pytest.fixture(scope="module")
def small_run() -> report.SceneRun:
    return report.run_methods("sphere", 48)


def test_every_method_is_compared_with_the_reference(small_run) -> None:
    assert list(small_run.results) == list(report.METHOD_LABELS)
    exact = small_run.results["exact"].comparison
    assert exact.nmse == 0.0 and exact.max_abs_error == 0.0
    for r in small_run.results.values():
        assert r.frame.stats.pixels_shaded > 0 and r.seconds > 0
    # The highlight mask is where (a)'s specular term passes 8 levels: a visible highlight.
    assert small_run.highlight.sum() > 0


def test_table_bits_count_the_roms_each_method_holds() -> None:
    assert report.table_bits("exact") == 0
    assert report.table_bits("gouraud") == divider.DEFAULT.rom_bits == 2048 * 21
    assert report.table_bits("hybrid") == divider.DEFAULT.rom_bits + specular.DEFAULT.rom_bits
    assert specular.DEFAULT.rom12_bits == 4 * 4096 * 16  # four cos^k tables
    assert report.table_bits("prototype") < report.table_bits("hybrid")  # one table


def test_table_and_requirements_text(small_run) -> None:
    table = report.format_table(small_run)
    assert table.count("\n| (") == len(report.METHOD_LABELS)
    req = report.requirements(small_run)
    assert "n values used: 60 -> 1 of the 1000 ROM-9 entries" in req
    assert "cos^k tables for k = 16" in req
    assert "adaptive:" in req and "through the specular unit" in req


def test_images_written(small_run, tmp_path) -> None:
    written = report.write_images(small_run, tmp_path)
    names = {p.name for p in written}
    assert "sphere_sheet.png" in names
    assert {f"sphere_{m}.png" for m in report.METHOD_LABELS} <= names
    assert all(p.stat().st_size > 0 for p in written)


def test_demo_command(tmp_path, capsys) -> None:
    assert main(["demo", "--scene", "sphere", "--size", "32", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "What the scene requires" in out and (tmp_path / "sphere_sheet.png").exists()


def test_unknown_method_and_bad_size() -> None:
    with pytest.raises(ValueError, match="method = 'phong2' is out of range"):
        report.shader_for("phong2")
    with pytest.raises(SystemExit):
        main(["demo", "--size", "4"])


def test_diffuse_method_is_h_and_counts_its_diffuse_cycles(small_run) -> None:
    from model.render.pipeline import PipelineConfig

    r = small_run.results["diffuse"]
    assert r.label == "(h) units: diffuse through the specular unit (n = 1)"
    assert (
        r.counters["diffuse_cycles"] > 0 == small_run.results["hybrid"].counters["diffuse_cycles"]
    )
    assert "| (h) units: diffuse" in report.format_table(small_run)
    # The specular unit's ROMs are needed as soon as the diffuse term goes through it.
    assert report.table_bits("diffuse") == report.table_bits("hybrid")
    both_vertex = PipelineConfig(specular_mode="vertex", diffuse_mode="unit")
    assert report.table_bits("x", both_vertex) == report.table_bits("hybrid")
