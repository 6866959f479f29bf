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
def run() -> report.SceneRun:
    return report.run_methods("teapot", 256)


def test_readme_method_rows_are_the_measured_ones(run: report.SceneRun) -> None:
    rows = ROW.findall(README.read_text())
    assert [name for _, name, *_ in rows] == list(run.results), rows
    for _, name, nmse, max_err, bits in rows:
        r = run.results[name]
        measured = (f"{r.comparison.nmse:.6f}", f"{r.comparison.max_abs_error:.0f}", r.table_bits)
        assert (nmse, max_err, int(bits)) == measured, name
