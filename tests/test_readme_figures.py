# SPDX-License-Identifier: Apache-2.0
"""The README's method table is what ``make demo`` measures (teapot, 256 x 256).

Each row's NMSE (6 decimals), max error (levels) and table bits are recomputed in-process with
``model.study.report.run_methods`` — the demo's own call — and compared with the README text.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from model.study import report

README = Path(__file__).resolve().parent.parent / "README.md"
ROW = re.compile(r"^\| \((\w)\) `(\w+)` \| [^|]+ \| ([0-9.]+) \| (\d+) \| (\d+) \|$", re.M)


@pytest.fixture(scope="module")
def run(teapot_file) -> report.SceneRun:
    return report.run_methods("teapot", 256)


def test_readme_method_rows_are_the_measured_ones(run: report.SceneRun) -> None:
    rows = ROW.findall(README.read_text())
    assert [name for _, name, *_ in rows] == list(run.results), rows
    for _, name, nmse, max_err, bits in rows:
        r = run.results[name]
        measured = (f"{r.comparison.nmse:.6f}", f"{r.comparison.max_abs_error:.0f}", r.table_bits)
        assert (nmse, max_err, int(bits)) == measured, name


SCENES_DOC = Path(__file__).resolve().parent.parent / "docs" / "scenes.md"
DOC_ROW = re.compile(r"^\| \((\w)\) [^|]+ \|((?: [^|]+ \|){11})$", re.M)


def _cells(r: report.MethodResult) -> list[str]:
    c, k = r.comparison, r.counters
    nmse = "0" if c.nmse == 0 else f"{c.nmse:.6f}" + (" ✓" if c.visually_identical else "")
    psnr = "inf" if c.psnr == float("inf") else f"{c.psnr:.1f}"
    counts = [
        str(k.get(n, "-"))
        for n in (
            "divider_cycles",
            "gouraud_cycles",
            "specular_cycles",
            "specular_pixels",
            "diffuse_cycles",
        )
    ]
    return [
        nmse,
        psnr,
        f"{c.max_abs_error:.0f}",
        f"{100 * c.share_off_by_more_than_1:.2f} %",
        f"{c.highlight_max_abs_error:.0f}",
        *counts,
        str(r.table_bits),
    ]


def test_scenes_page_measured_table_is_the_demo_table(run: report.SceneRun) -> None:
    rows = DOC_ROW.findall(SCENES_DOC.read_text())
    assert len(rows) == len(run.results), rows
    for (letter, cells), r in zip(rows, run.results.values(), strict=True):
        assert r.label.startswith(f"({letter})"), (letter, r.label)
        assert [x.strip() for x in cells.strip(" |").split("|")] == _cells(r), r.label


def test_scenes_page_per_scene_nmse_at_128(teapot_file) -> None:
    """The sentence 'measured NMSE 0.000008 (quad), 0.000059 (sphere), ...' and the ranges of the
    prototype and Gouraud only, recomputed over the four built-in scenes at 128 x 128."""
    text = " ".join(SCENES_DOC.read_text().split())
    nmse = {}
    for name in ("quad", "sphere", "teapot", "torus"):
        run = report.run_methods(name, 128, methods=["hybrid", "prototype", "gouraud"])
        nmse[name] = {m: r.comparison.nmse for m, r in run.results.items()}
    hybrid = ", ".join(
        f"{nmse[s]['hybrid']:.6f} ({s})" for s in ("quad", "sphere", "teapot", "torus")
    )
    assert f"measured NMSE {hybrid}" in text
    proto = [v["prototype"] for v in nmse.values()]
    gouraud = [v["gouraud"] for v in nmse.values()]
    assert f"the prototype: {min(proto):.5f}-{max(proto):.5f}" in text
    assert f"Gouraud only: {min(gouraud):.5f}-{max(gouraud):.4f}" in text
