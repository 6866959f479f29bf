# SPDX-License-Identifier: Apache-2.0
"""cocotb bench of rtl/divider_shift.v against model.divider (run by tests/test_sim_divider.py)."""

from __future__ import annotations

import itertools

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge

from model.units import divider
from model.units.divider import DividerConfig
from sim.common import (
    ProtocolMonitor,
    UnitTB,
    bench_config,
    bench_rng,
    random_strobes,
)

# Above this many (a, k) pairs the operand space is sampled instead of walked exhaustively.
EXHAUSTIVE_LIMIT = 20_000
# Random divisions where the space is sampled: a scoreboard check of arbitrary operands.  The
# bulk random checking of the divider is the vector soak's (tests/test_soak.py
# ``test_soak_every_output_every_cycle``, sim/soak.py: 100 000 cycles of the default
# configuration, 20 000 of article and n4), with no Python in the loop.
RANDOM_DIVISIONS = 200


class DividerTB(UnitTB):
    """Driver + scoreboard for one divider configuration."""

    def __init__(self, dut) -> None:
        self.cfg = DividerConfig(**bench_config())
        super().__init__(dut, ProtocolMonitor(dut, self.cfg))

    async def divide(self, a: int, k: int) -> None:
        """One division: operands and start in consecutive cycles, then wait for the result."""
        await self.run(a=a, k=k)

    def extreme_dividends(self) -> list[int]:
        lo, hi = self.cfg.a_range
        return sorted({lo, lo + 1, -1, 0, 1, hi - 1, hi})

    def extreme_divisors(self) -> list[int]:
        k_max = self.cfg.k_max
        powers = [1 << i for i in range(self.cfg.k_width)]
        return sorted({0, 1, 2, 3, k_max - 1, k_max, *powers})


@cocotb.test()
async def test_every_or_random_quotient(dut):
    """Exhaustive over (a, k) when the space is small (the article's case), else a sample of
    random divisions (the bulk random checking is the vector soak's, tests/test_soak.py)."""
    tb = DividerTB(dut)
    await tb.reset()
    lo, hi = tb.cfg.a_range
    pairs = (hi - lo + 1) * (tb.cfg.k_max + 1)
    if pairs <= EXHAUSTIVE_LIMIT:
        dut._log.info("exhaustive: %d dividends x %d divisors", hi - lo + 1, tb.cfg.k_max + 1)
        for k in range(tb.cfg.k_max + 1):
            for a in range(lo, hi + 1):
                await tb.divide(a, k)
        assert tb.monitor.stats.results_compared == pairs
    else:
        rng = bench_rng("random")
        for _ in range(RANDOM_DIVISIONS):
            await tb.divide(rng.randint(lo, hi), rng.randint(1, tb.cfg.k_max))
        assert tb.monitor.stats.results_compared == RANDOM_DIVISIONS
    tb.monitor.finish("every_or_random_quotient")


@cocotb.test()
async def test_extremes(dut):
    """The most negative dividend, 0, +-1, the largest; k = 0, 1, powers of two, the largest."""
    tb = DividerTB(dut)
    await tb.reset()
    cases = list(itertools.product(tb.extreme_dividends(), tb.extreme_divisors()))
    for a, k in cases:
        await tb.divide(a, k)
    assert tb.monitor.stats.results_compared == len(cases)
    tb.monitor.finish("extremes")


@cocotb.test()
async def test_writes_and_start_ignored_while_busy(dut):
    """Rule 1: operand writes and start pulses during a division change nothing."""
    tb = DividerTB(dut)
    await tb.reset()
    rng = bench_rng("busy")
    lo, hi = tb.cfg.a_range
    for _ in range(20):
        k = rng.randint(1, tb.cfg.k_max)
        await tb.load(a=rng.randint(lo, hi), k=k)
        await tb.start()
        await tb.hammer_while_busy(
            divider.cycles(k, tb.cfg),
            lambda: {"a": rng.randint(lo, hi), "k": rng.randint(0, tb.cfg.k_max)},
        )
    stats = tb.monitor.finish("busy_ignored")
    assert stats.writes_ignored > 0 and stats.starts_ignored > 0


@cocotb.test()
async def test_back_to_back(dut):
    """Rule 3: a start in the first cycle busy is 0 is accepted; new operands in between."""
    tb = DividerTB(dut)
    await tb.reset()
    rng = bench_rng("b2b")
    lo, hi = tb.cfg.a_range
    await tb.load(a=rng.randint(lo, hi), k=rng.randint(1, tb.cfg.k_max))
    await tb.start()
    for _ in range(30):
        await tb.start_when_ready()
    await tb.monitor.wait_idle()
    stats = tb.monitor.finish("back_to_back")
    assert stats.back_to_back == 30, stats


@cocotb.test()
async def test_reset_mid_division(dut):
    """Rule 4: rst_n low during a division aborts it; registers are cleared (k = 0 after)."""
    tb = DividerTB(dut)
    await tb.reset()
    rng = bench_rng("reset")
    lo, hi = tb.cfg.a_range
    for _ in range(10):
        k = rng.randint(3, tb.cfg.k_max)
        await tb.load(a=rng.randint(lo, hi), k=k)
        await tb.start()
        await tb.cycles(rng.randint(0, max(0, divider.cycles(k, tb.cfg) - 2)))
        await tb.reset(cycles=rng.randint(1, 3))
        # Cleared registers: a start without loading divides 0 by 0 (div_zero, q = 0).
        await tb.start()
        await tb.monitor.wait_idle()
    stats = tb.monitor.finish("reset_mid_division")
    assert stats.jobs_aborted >= 10, stats


@cocotb.test()
async def test_mismatch_report_reproduces(dut):
    """Rule 6: the scoreboard flags a wrong result and names the inputs that reproduce it."""
    tb = DividerTB(dut)
    tb.monitor.corrupt_model(0, "q", lambda q: q + 1)
    await tb.reset()
    await tb.divide(-5, 3)
    errors = tb.monitor.stats.errors
    assert len(errors) == 1 and "a=-5, k=3" in errors[0], errors
    # The reported inputs reproduce the RTL's value with the model directly.
    assert f"'q': {divider.divide(-5, 3, tb.cfg)}" in errors[0], errors[0]
    errors.clear()
    tb.monitor.finish("mismatch_report")


@cocotb.test()
async def test_random_strobes(dut):
    """Rules 1-7 under the soak's stimulus: random strobes, start timing and resets, writes in
    start and busy cycles, values across 0 and at the extremes; every output, every cycle."""
    await random_strobes(DividerTB(dut))


@cocotb.test()
async def test_write_in_start_cycle(dut):
    """Rule 7, the issue-11 cases: a k write in the start cycle is for the next division.

    k = 0 loaded, k = 3 written with start: this division has div_zero = 1, q = 0; then k = 4
    loaded, k = 0 written with start: div_zero = 0, q = 100 * round(2^N / 4).  The values are
    asserted from the documented behaviour, not only against the model.
    """
    tb = DividerTB(dut)
    await tb.reset()
    tb.monitor.keep_results = True
    n = tb.cfg.recip_bits
    await tb.load(a=100, k=0)
    tb.drive_operands(k=3)
    await tb.start()
    tb.release_strobes()
    await tb.monitor.wait_idle()
    await tb.load(k=4)
    tb.drive_operands(k=0)
    await tb.start()
    tb.release_strobes()
    await tb.monitor.wait_idle()
    stats = tb.monitor.finish("write_in_start_cycle")
    assert stats.writes_at_start == 2, stats
    got = [job[0] for job in tb.monitor.result_log]
    assert got == [{"q": 0, "div_zero": 1}, {"q": 100 << (n - 2), "div_zero": 0}], got


@cocotb.test()
async def test_rom_read_on_the_k_write(dut):
    """The reciprocal ROM is read when k is written (not at start): right after an idle-cycle k
    write the working register holds ROM word k of the model's image."""
    tb = DividerTB(dut)
    await tb.reset()
    words = divider.rom_words(tb.cfg)
    rng = bench_rng("rom_read")
    for k in sorted({0, 1, 2, 3, tb.cfg.k_max, *(rng.randint(0, tb.cfg.k_max) for _ in range(20))}):
        await tb.load(k=k)
        await ReadOnly()
        rom_q = dut.u_recip_rom.q_a_reg  # the ROM module's read register
        assert rom_q.value.to_unsigned() == int(words[k]), (k, rom_q.value)
        await RisingEdge(dut.clk)
    tb.monitor.finish("rom_read_on_the_k_write")
