# SPDX-License-Identifier: Apache-2.0
"""Run the shading core's cocotb bench (sim/tb_shading_core.py: cocotbext-axi source, sink and
monitor, random idles and stalls, every pixel beat scoreboarded against
model.render.core.core_pixels) under SIM (Icarus by default), at the default configuration
(``METHODS["diffuse"]``: both the highlight and the diffuse path built)."""

from __future__ import annotations

import pytest

from model.render.core import SpanFormat
from model.render.pipeline import METHODS
from sim import core_run
from sim.runner import run_bench
from tests.conftest import record_sim

pytestmark = pytest.mark.sim

METHOD = "diffuse"
TESTS = [
    "test_random_spans_idles_and_stalls",
    "test_reset_mid_frame",
    "test_shortest_and_longest_spans",
    "test_saturating_sum",
    "test_stalled_beats_held",
    "test_mismatch_report_reproduces",
]


def test_core_rtl_matches_model(request) -> None:
    cfg = METHODS[METHOD]
    fmt = SpanFormat(cfg)
    records = run_bench(
        "shading_core",
        "sim.tb_shading_core",
        f"shading_core_{METHOD}",
        core_run.parameters(cfg),
        {"method": METHOD, "x_width": fmt.x_width, "y_width": fmt.y_width},
    )
    record_sim(request, records)
    assert sorted(r["test"] for r in records) == sorted(t.removeprefix("test_") for t in TESTS)
    assert all(r["errors"] == 0 for r in records), records
    # Every pixel beat compared, and each span came out as one frame to the sink and the
    # monitor alike.
    assert sum(r["compared"] for r in records) > 3000, records
    reset = next(r for r in records if r["test"] == "reset_mid_frame")
    assert reset["resets"] == 4 and reset["stale_beats"] == 0, reset
    held = next(r for r in records if r["test"] == "stalled_beats_held")
    assert held["held"] == held["stalls"] > 0, held
