# SPDX-License-Identifier: Apache-2.0
"""Run the divider's cocotb bench under Icarus (or SIM) for several configurations; the
runner's SIM handling: a bad value refused in one line, a Verilator too old for cocotb refused
before any build, naming the version found and the one needed."""

from __future__ import annotations

from xml.etree import ElementTree

import pytest

from model.units import divider
from sim import runner
from sim.common import CLOCK_NS, WATCHDOG_CYCLES
from sim.runner import SIM_BUILD, hdl_parameters, run_bench, simulator
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
    # (Verilator is two-state: no X at all.)
    four_state = simulator() == "icarus"
    assert (x_cycles > 0) if reset_all == 0 and four_state else (x_cycles == 0), records


def test_bench_finds_the_div_zero_leak(request) -> None:
    """The released divider (div_zero read from the k register at result time) fails
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
    first = [e for r in records for e in r["first_errors"]]
    assert first and all("div_zero" in e for e in first), first


def test_stuck_busy_fails_instead_of_hanging(request) -> None:
    """A divider whose busy never falls fails the bench's extremes test (the watchdog of
    ``wait_idle``), it does not hang it: the failure cocotb records is the watchdog's
    SimTimeoutError, raised WATCHDOG_CYCLES clock periods into the test."""
    cfg = divider.DEFAULT
    params = hdl_parameters(cfg, ROM_FILE=divider.rom_path(cfg))
    name = "divider_mutant_busy_stuck"
    records = run_bench(
        "divider_shift",
        "sim.tb_divider",
        name,
        params,
        cfg,
        testcase="test_extremes",
        rtl=mutants.build("divider_shift_busy_stuck", SIM_BUILD / "mutants"),
        expect_failure=True,
    )
    assert records == [], records  # the test failed before it could finish its summary
    # run_bench's build folder for the default RESET_ALL = 0 (a suffix for another simulator)
    build_dir = SIM_BUILD / (name if simulator() == "icarus" else f"{name}-{simulator()}")
    cases = ElementTree.parse(build_dir / "results.xml").getroot().iter("testcase")
    (case,) = [c for c in cases if c.get("name") == "test_extremes"]
    failures = case.findall("failure")
    assert [f.get("type") for f in failures] == ["SimTimeoutError"], ElementTree.tostring(case)
    assert "wait_idle" in (failures[0].text or ""), failures[0].text  # the watchdog's own timeout
    stop = {p.get("name"): p.get("value") for p in case.iter("property")}["sim_time_stop"]
    assert float(stop) >= WATCHDOG_CYCLES * CLOCK_NS, stop


def test_bench_finds_a_one_cycle_glitch_between_events(request) -> None:
    """div_zero flips for one cycle in the middle of each division and back (the saved mutant
    ``divider_shift_div_zero_glitch``): in that cycle the model predicts no change, so only
    the output's own value change wakes the event-driven monitor, which must report it as a
    held flag that changed between results, with the job's inputs."""
    cfg = divider.DEFAULT
    params = hdl_parameters(cfg, ROM_FILE=divider.rom_path(cfg))
    records = run_bench(
        "divider_shift",
        "sim.tb_divider",
        "divider_mutant_div_zero_glitch",
        params,
        cfg,
        testcase="test_extremes",
        rtl=mutants.build("divider_shift_div_zero_glitch", SIM_BUILD / "mutants"),
        expect_failure=True,
    )
    assert len(records) == 1 and records[0]["errors"] > 0, records
    # A division of two or more busy cycles glitches in a cycle between results (k = 0 and 1
    # take one busy cycle: there it lands on the result and is a result mismatch).
    first = records[0]["first_errors"]
    assert all("div_zero" in e and ", k=" in e for e in first), first
    assert any("between results: div_zero = 1, expected 0" in e for e in first), first
    assert records[0]["wakes"] < records[0]["cycles"], records  # event-driven, not per cycle


def test_a_bad_sim_is_refused_in_one_line(monkeypatch, tmp_path) -> None:
    monkeypatch.setenv("SIM", "questa")
    cfg = divider.DEFAULT
    with pytest.raises(ValueError) as caught:
        run_bench("divider_shift", "sim.tb_divider", "divider_bad_sim", {}, cfg)
    message = str(caught.value)
    assert "\n" not in message and message.startswith("SIM='questa' is not allowed"), message
    assert "icarus, verilator" in message, message
    assert not (SIM_BUILD / "divider_bad_sim").exists()  # refused before any build
    for value, sim in [("", "icarus"), ("icarus", "icarus"), ("Verilator", "verilator")]:
        monkeypatch.setenv("SIM", value)
        assert runner.simulator() == sim
    monkeypatch.delenv("SIM")
    assert runner.simulator() == "icarus"


def test_a_verilator_too_old_for_cocotb_is_refused() -> None:
    """cocotb 2.x's Verilator main needs VerilatedVpi::evalNeeded (Verilator 5.036 on): an
    older one is refused with both versions named, a new enough one accepted."""
    needed = runner.verilator_min()
    assert runner.version_key(needed) >= (5, 0), needed
    old = runner.verilator_problem("Verilator 5.006 2023-01-22 rev (Debian 5.006-3)\n", "5.036")
    assert old and "Verilator 5.036 or later" in old and "found Verilator 5.006" in old, old
    assert "SIM=icarus" in old and "\n" not in old, old
    assert runner.verilator_problem("Verilator 5.036 2025-04-27 rev v5.036", "5.036") is None
    assert runner.verilator_problem("Verilator 5.040 2025-08-30 rev v5.040", "5.036") is None
    assert runner.verilator_problem("Verilator 5.100 devel", "5.036") is None
    assert "cannot read a version" in runner.verilator_problem("command not found", "5.036")
