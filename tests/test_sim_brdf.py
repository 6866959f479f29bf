# SPDX-License-Identifier: Apache-2.0
"""Run the BRDF unit's cocotb bench (sim/tb_brdf.py) under SIM (Icarus by default): each form
with RTL at its default widths (``brdf.UNIT_CONFIGS``), RESET_ALL = 0 and, for the tests that
reset, 1; the piecewise form also at two other widths (its datapath's width cases); and the
saved mutants ``brdf_unit_round_quarter``, for the cubic ``brdf_unit_cubic_b_word``, for the
log2 form ``brdf_log2_octave_bit`` and for the piecewise form ``brdf_div_no_restore`` and
``brdf_piecewise_gate_stage`` (tests/mutants), which it must fail naming intensity."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from model.units import brdf, specular
from model.units.brdf import FixedConfig
from sim.runner import SIM_BUILD, run_bench, simulator
from tests import mutants
from tests.conftest import record_sim

pytestmark = pytest.mark.sim

RESET_ALL_TESTS = ["test_extremes", "test_reset_mid_line", "test_random_strobes"]


def _run(name: str, reset_all: int, build: str = "", **kwargs) -> list[dict]:
    """The bench on form ``name``'s default widths, built in sim_build/brdf_<name><build>: a
    mutant's build must have a folder of its own (tests run side by side under xdist)."""
    cfg = brdf.UNIT_CONFIGS[name]
    return run_bench(
        "brdf_unit",
        "sim.tb_brdf",
        f"brdf_{name}{build}",
        brdf.hdl_parameters(cfg),
        cfg,
        reset_all=reset_all,
        **kwargs,
    )


@pytest.mark.parametrize("name", list(brdf.UNIT_CONFIGS))
def test_brdf_rtl_matches_model(request, name: str) -> None:
    """Every test of the bench at RESET_ALL = 0: every n = 1..1000 through the unit, the
    extremes, the protocol probes, random strobes; every output compared in every cycle."""
    records = _run(name, 0)
    record_sim(request, records)
    by_test = {r["test"]: r for r in records}
    assert by_test["every_n_random_lines"]["jobs"] >= specular.N_MAX + 4, records
    assert by_test["extremes"]["compared"] > 10_000, records
    assert all(r["errors"] == 0 for r in records), records
    # Data outputs X between a reset and the first result: the data path is not reset
    # (Verilator is two-state: no X at all).
    x_cycles = sum(r["x_data_cycles"] for r in records)
    assert (x_cycles > 0) if simulator() == "icarus" else (x_cycles == 0), records


@pytest.mark.parametrize("name", list(brdf.UNIT_CONFIGS))
def test_brdf_rtl_reset_all(request, name: str) -> None:
    """RESET_ALL = 1: the tests that reset, with the data outputs 0 from a reset on."""
    records = _run(name, 1, testcase=RESET_ALL_TESTS)
    record_sim(request, records)
    assert {r["test"] for r in records} == {"extremes", "reset_mid_line", "random_strobes"}
    assert all(r["reset_all"] == 1 and r["x_data_cycles"] == 0 for r in records), records


def test_bench_fails_on_the_round_quarter_mutant(request) -> None:
    """The output rounding's constant a bit too low (a quarter LSB): the bench fails, every
    error it reports is an intensity mismatch of a named job."""
    records = _run(
        "cosine_quadratic",
        0,
        build="_round_quarter",
        testcase=["test_extremes"],
        rtl=mutants.build("brdf_unit_round_quarter", SIM_BUILD / "mutants"),
        expect_failure=True,
    )
    record_sim(request, records)
    errors = [e for r in records for e in r["first_errors"]]
    assert sum(r["errors"] for r in records) > 0 and errors, records
    assert all("mismatch" in e and "'intensity'" in e and "reproduce with" in e for e in errors)


def test_bench_fails_on_the_cubic_b_word_mutant(request) -> None:
    """The cubic's b1 and b2 read from the word of r and p0: the bench fails, every error it
    reports is an intensity mismatch of a named job."""
    records = _run(
        "cubic",
        0,
        build="_b_word",
        testcase=["test_extremes"],
        rtl=mutants.build("brdf_unit_cubic_b_word", SIM_BUILD / "mutants"),
        expect_failure=True,
    )
    record_sim(request, records)
    errors = [e for r in records for e in r["first_errors"]]
    assert sum(r["errors"] for r in records) > 0 and errors, records
    assert all("mismatch" in e and "'intensity'" in e and "reproduce with" in e for e in errors)


def test_bench_fails_on_the_log2_octave_bit_mutant(request) -> None:
    """The log2 datapath's f in the second octave from the wrong bit of x (rtl/brdf_log2.v
    replaced by the mutant): the bench fails, every error it reports is an intensity mismatch
    of a named job."""
    records = _run(
        "log2",
        0,
        build="_octave_bit",
        testcase=["test_extremes"],
        rtl=mutants.build("brdf_log2_octave_bit", SIM_BUILD / "mutants"),
        replaces="brdf_log2.v",
        expect_failure=True,
    )
    record_sim(request, records)
    errors = [e for r in records for e in r["first_errors"]]
    assert sum(r["errors"] for r in records) > 0 and errors, records
    assert all("mismatch" in e and "'intensity'" in e and "reproduce with" in e for e in errors)


@pytest.mark.parametrize(
    ("mutant", "replaces"),
    [("brdf_div_no_restore", "brdf_div.v"), ("brdf_piecewise_gate_stage", "brdf_piecewise.v")],
)
def test_bench_fails_on_the_piecewise_mutants(request, mutant: str, replaces: str) -> None:
    """The piecewise form's divider without its restoring step, and its dividend gated by the
    next pixel's branch (the file replaced by the mutant): the bench fails, every error it
    reports is an intensity mismatch of a named job."""
    records = _run(
        "piecewise",
        0,
        build=f"_{mutant}",
        testcase=["test_extremes"],
        rtl=mutants.build(mutant, SIM_BUILD / "mutants"),
        replaces=replaces,
        expect_failure=True,
    )
    record_sim(request, records)
    errors = [e for r in records for e in r["first_errors"]]
    assert sum(r["errors"] for r in records) > 0 and errors, records
    assert all("mismatch" in e and "'intensity'" in e and "reproduce with" in e for e in errors)


# The piecewise datapath's other width cases (rtl/brdf_piecewise.v): den shifted up instead of
# c (P + O < D) with fewer quotient stages than the cubic's (O < 6: the quotient waits, 14
# stages), 21-bit coefficients (63-bit ROM words); and r w and s2 scaled up (negative
# rounding shifts), a 25-bit quotient (32 stages), C x F with a 16-bit C and output, so that F
# is compared nearly to its last bit
PIECEWISE_WIDTHS = {
    "narrow": FixedConfig("piecewise", coef_bits=21, work_bits=8, out_bits=4),
    "wide": FixedConfig(
        "piecewise", cos_addr_bits=10, cos_data_bits=6, coef_bits=11, work_bits=16, out_bits=24,
        angle=replace(specular.DEFAULT, c_int_bits=16, c_frac_bits=0, out_width=16),
    ),
}  # fmt: skip


@pytest.mark.parametrize("name", list(PIECEWISE_WIDTHS))
def test_piecewise_rtl_at_other_widths(request, name: str, tmp_path: Path) -> None:
    """The piecewise form at widths other than its default (images written for them): every
    n through the unit and the extremes, every output compared in every cycle."""
    cfg = PIECEWISE_WIDTHS[name]
    params = brdf.hdl_parameters(cfg)
    for which in brdf.rom_kinds(cfg):
        path = tmp_path / brdf.rom_name(cfg, which)
        path.write_text(brdf.rom_text(cfg, which))
        params[f"{which.upper()}_ROM_FILE"] = str(path)
    records = run_bench(
        "brdf_unit",
        "sim.tb_brdf",
        f"brdf_piecewise_{name}",
        params,
        cfg,
        testcase=["test_every_n_random_lines", "test_extremes"],
    )
    record_sim(request, records)
    by_test = {r["test"]: r for r in records}
    assert by_test["every_n_random_lines"]["jobs"] >= specular.N_MAX + 4, records
    assert all(r["errors"] == 0 for r in records), records
