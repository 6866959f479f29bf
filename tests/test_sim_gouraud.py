# SPDX-License-Identifier: Apache-2.0
"""Run the segment Gouraud unit's cocotb bench under SIM (Icarus by default) for several
configurations."""

from __future__ import annotations

import pytest

from model.units.gouraud import GouraudConfig
from sim.runner import hdl_parameters, run_bench, simulator
from tests.conftest import record_sim

pytestmark = pytest.mark.sim

# P = 2, 4, 8 with the default 12 fraction bits and a coarse 4; P = 16 exercises the
# increment network's second adder level (11 = 10+1, 13 = 12+1).
CONFIGS = {f"p{p}_f{f}": GouraudConfig(p=p, i_frac=f) for p in (2, 4, 8) for f in (12, 4)}
CONFIGS["p16_f12"] = GouraudConfig(p=16, i_frac=12)


# Every configuration with RESET_ALL = 0 (the default: the data path is not reset, and Icarus
# starts it at X); RESET_ALL = 1 on P = 8 and P = 16, the tests that reset.
REGRESSIONS = [(name, 0) for name in CONFIGS] + [("p8_f12", 1), ("p16_f12", 1)]
RESET_ALL_TESTS = ["test_reset_mid_line", "test_random_strobes"]


@pytest.mark.parametrize(("name", "reset_all"), REGRESSIONS)
def test_gouraud_rtl_matches_model(request, name: str, reset_all: int) -> None:
    cfg = CONFIGS[name]
    params = hdl_parameters(cfg)
    records = run_bench(
        "gouraud_segment",
        "sim.tb_gouraud",
        f"gouraud_{name}",
        params,
        cfg,
        testcase=RESET_ALL_TESTS if reset_all else None,
        reset_all=reset_all,
    )
    record_sim(request, records)
    tests = len(RESET_ALL_TESTS) if reset_all else 9
    assert len(records) == tests and all(r["errors"] == 0 for r in records), records
    assert sum(r["compared"] for r in records) > 0
    assert all(r["reset_all"] == reset_all for r in records), records
    # Data outputs X between a reset and the first result only where the data path is unreset
    x_cycles = sum(r["x_data_cycles"] for r in records)
    # (Verilator is two-state: no X at all.)
    four_state = simulator() == "icarus"
    assert (x_cycles > 0) if reset_all == 0 and four_state else (x_cycles == 0), records
