# SPDX-License-Identifier: Apache-2.0
"""The scaling measurements of ``make bench`` (model/study/scaling.py): both axes measured for
every method, the table and the plot written.  No speed is asserted (a benchmark, not a test)."""

from __future__ import annotations

from pathlib import Path

from model.study import scaling


def test_scaling_rows_table_and_plot(teapot_file, tmp_path: Path) -> None:
    rows = scaling.scaling(sizes=(16, 32), subdivisions=(0, 1), mesh_size=32, repeats=1,
                           progress=False)  # fmt: skip
    assert len(rows) == (2 + 2) * len(scaling.METHODS)
    sizes = [r for r in rows if r["axis"] == "size"]
    assert {r["size"] for r in sizes} == {16, 32} and {r["method"] for r in sizes} == set(
        scaling.METHODS
    )
    tri = sorted({r["triangles"] for r in rows if r["axis"] == "triangles"})
    assert tri == [20, 80]  # icospheres of 20 * 4**k triangles
    assert all(r["mpx_per_s"] > 0 and r["pixels"] > 0 for r in rows)
    text = scaling.format_scaling(rows)
    assert "| teapot, image side | exact Mpx/s | hybrid Mpx/s | adaptive Mpx/s |" in text
    assert "| icosphere, triangles |" in text and "\n| 80 |" in text
    png = scaling.plot_scaling(rows, tmp_path / "scaling.png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
