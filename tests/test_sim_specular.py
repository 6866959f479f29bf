# SPDX-License-Identifier: Apache-2.0
"""Run the specular unit's cocotb bench under SIM (Icarus by default): the default, narrow and
UP5K configurations, the narrow one that keeps n = 17..40 only (``specular.KEPT``), and the
default with RESET_ALL = 1."""

from __future__ import annotations

import pytest

from model.units import specular
from sim.runner import run_bench, simulator
from tests.conftest import record_sim

pytestmark = pytest.mark.sim


# Every configuration with RESET_ALL = 0 (the default: the data path is not reset, and Icarus
# starts it at X); RESET_ALL = 1 on the default configuration only, the tests that reset.
REGRESSIONS = [(name, 0) for name in ("default", "narrow", "up5k", "kept")] + [("default", 1)]
BENCHED = {**specular.ROM_CONFIGS, **specular.KEPT_CONFIGS}
RESET_ALL_TESTS = ["test_extremes", "test_reset_mid_line", "test_random_strobes"]


@pytest.mark.parametrize(("name", "reset_all"), REGRESSIONS)
def test_specular_rtl_matches_model(request, name: str, reset_all: int) -> None:
    cfg = BENCHED[name]
    records = run_bench(
        "specular_unit",
        "sim.tb_specular",
        f"specular_{name}",
        cfg.hdl_parameters(),
        cfg,
        testcase=RESET_ALL_TESTS if reset_all else None,
        reset_all=reset_all,
    )
    record_sim(request, records)
    assert sum(r["compared"] for r in records) > 0
    assert all(r["reset_all"] == reset_all for r in records), records
    # Data outputs X between a reset and the first result only where the data path is unreset
    x_cycles = sum(r["x_data_cycles"] for r in records)
    # (Verilator is two-state: no X at all.)
    four_state = simulator() == "icarus"
    assert (x_cycles > 0) if reset_all == 0 and four_state else (x_cycles == 0), records
    if reset_all == 0:
        # Every n = 1..1000 went through the unit (the every-n test counts its own lines): for
        # "kept" that is n_first - 1, n_first, n_last, n_last + 1 and every n it drops.
        every_n = [r for r in records if r["test"] == "every_n_random_lines"]
        assert every_n and every_n[0]["jobs"] >= specular.N_MAX
