# SPDX-License-Identifier: Apache-2.0
"""Run the divider's cocotb bench under Icarus for several configurations."""

from __future__ import annotations

import pytest

from model.units import divider
from sim.runner import SIM_BUILD, hdl_parameters, run_bench
from tests import mutants
from tests.conftest import record_sim

pytestmark = pytest.mark.sim


# Every configuration with RESET_ALL = 0 (the default: the data path is not reset, and Icarus
# starts it at X); RESET_ALL = 1 on the default configuration only, the tests that reset.
REGRESSIONS = [(name, 0) for name in ("article", "n4", "n16", "default")] + [("default", 1)]
RESET_ALL_TESTS = ["test_extremes", "test_reset_mid_division", "test_random_strobes"]


@pytest.mark.parametrize(("name", "reset_all"), REGRESSIONS)
def test_divider_rtl_matches_model(request, name: str, reset_all: int) -> None:
    cfg = divider.ROM_CONFIGS[name]
    params = hdl_parameters(cfg, ROM_FILE=divider.rom_path(cfg))
    records = run_bench(
        "divider_shift",
        "sim.tb_divider",
        f"divider_{name}",
        params,
        cfg,
        testcase=RESET_ALL_TESTS if reset_all else None,
        reset_all=reset_all,
    )
    record_sim(request, records)
    assert sum(r["compared"] for r in records) > 0
    assert all(r["reset_all"] == reset_all for r in records), records
    # Data outputs X between a reset and the first result only where the data path is unreset
    x_cycles = sum(r["x_data_cycles"] for r in records)
    assert (x_cycles > 0) if reset_all == 0 else (x_cycles == 0), records


def test_bench_finds_the_div_zero_leak(request) -> None:
    """The released divider (div_zero read from the k register at result time, issue 11) fails
    the bench's random-strobe and write-in-start-cycle tests: the deliberate-error probe kept
    as a saved mutant."""
    cfg = divider.DEFAULT
    params = hdl_parameters(cfg, ROM_FILE=divider.rom_path(cfg))
    records = run_bench(
        "divider_shift",
        "sim.tb_divider",
        "divider_mutant_div_zero",
        params,
        cfg,
        testcase=["test_random_strobes", "test_write_in_start_cycle"],
        rtl=mutants.build("divider_shift_div_zero_leak", SIM_BUILD / "mutants"),
        expect_failure=True,
    )
    errors = {r["test"]: r["errors"] for r in records}
    assert errors.get("random_strobes", 0) > 0 and errors.get("write_in_start_cycle", 0) > 0, (
        records
    )


def test_stuck_busy_fails_instead_of_hanging(request) -> None:
    """A divider whose busy never falls fails the bench's extremes test (the watchdog of
    ``wait_idle``), it does not hang it."""
    cfg = divider.DEFAULT
    params = hdl_parameters(cfg, ROM_FILE=divider.rom_path(cfg))
    records = run_bench(
        "divider_shift",
        "sim.tb_divider",
        "divider_mutant_busy_stuck",
        params,
        cfg,
        testcase="test_extremes",
        rtl=mutants.build("divider_shift_busy_stuck", SIM_BUILD / "mutants"),
        expect_failure=True,
    )
    assert records == [], records  # the test failed before it could finish its summary
