# SPDX-License-Identifier: Apache-2.0
"""cocotb bench of rtl/gouraud_segment.v against model.gouraud (run by tests/test_sim_gouraud.py).

Every segment (packed ``pixels``, ``mask``, ``last``) is compared bit for bit with
``gouraud.unit_results``; ``busy`` and ``valid`` cycle by cycle with ``gouraud.cycles`` and
``gouraud.valid_offsets`` (sim/common.py's ProtocolMonitor does all the checking).
"""

from __future__ import annotations

import random

import cocotb

from model.units import divider, fixed, gouraud
from model.units.gouraud import GouraudConfig
from sim.common import (
    ProtocolMonitor,
    UnitTB,
    bench_config,
    bench_rng,
    random_strobes,
)

# Random lines: the scoreboard on arbitrary operands and the three ways of loading them.  The
# bulk random checking of the unit is the vector soak's (tests/test_soak.py
# ``test_soak_every_output_every_cycle``, sim/soak.py: 100 000 cycles of the default
# configuration, 20 000 of P = 2 and P = 16), with no Python in the loop.
RANDOM_LINES = 40
BUSY_LINES = 15
BACK_TO_BACK = 20
RESETS = 8


class GouraudTB(UnitTB):
    """Driver + scoreboard for one configuration of the segment Gouraud unit."""

    def __init__(self, dut) -> None:
        self.cfg = GouraudConfig(**bench_config())
        super().__init__(dut, ProtocolMonitor(dut, self.cfg))
        # The increments a host would compute with the shift-add divider: (I_b - I_a) / (m - 1)
        self.div_cfg = divider.DividerConfig(
            a_width=self.cfg.di_width, k_width=self.cfg.len_width, recip_bits=20
        )

    async def line(self, i0: int, di: int, length: int) -> None:
        """One line: operands in one cycle, start in the next, wait until busy is low."""
        await self.run(i0=i0, di=di, len=length)

    # ------------------------------------------------------------------ operand choices
    def ramp_increment(self, i_a: int, i_b: int, length: int) -> int:
        """The increment from I_a to I_b over a line, by the shift-add divider (approximate:
        it may overshoot I_b, which the unit must saturate)."""
        if length < 2:
            return 0
        q = divider.divide(i_b - i_a, length - 1, self.div_cfg)
        return fixed.saturate(fixed.round_shift(q, self.div_cfg.recip_bits), *self.cfg.di_range)

    def random_length(self, rng: random.Random) -> int:
        p, len_max = self.cfg.p, self.cfg.len_max
        r = rng.random()
        if r < 0.4:
            return rng.randint(1, 2 * p + 1)
        if r < 0.75:
            return rng.randint(1, min(64, len_max))
        return rng.randint(1, len_max)

    def random_line(self, rng: random.Random) -> tuple[int, int, int]:
        i_lo, i_hi = self.cfg.i0_range
        d_lo, d_hi = self.cfg.di_range
        length = self.random_length(rng)
        i0 = rng.randint(i_lo, i_hi)
        r = rng.random()
        if r < 0.5:  # a ramp between two intensities, increment from the divider
            di = self.ramp_increment(i0, rng.randint(i_lo, i_hi), length)
        elif r < 0.75:  # small increments, either sign
            di = rng.randint(-(1 << self.cfg.i_frac), 1 << self.cfg.i_frac)
        else:  # anything legal (mostly saturating)
            di = rng.randint(d_lo, d_hi)
        return i0, di, length

    def directed_lengths(self) -> list[int]:
        p = self.cfg.p
        return sorted({1, p - 1, p, p + 1, 2 * p, 2 * p + 1})

    def directed_increments(self) -> list[int]:
        d_lo, d_hi = self.cfg.di_range
        third = (1 << self.cfg.i_frac) // 3
        return [0, 1, -1, third, -third, d_hi, d_lo, d_hi - 1, d_lo + 1]


@cocotb.test()
async def test_structure_matches_model(dut):
    """The RTL's widths and its increment network (constant functions) are the model's."""
    tb = GouraudTB(dut)
    cfg = tb.cfg
    assert len(dut.start_reg) == cfg.acc_width, (len(dut.start_reg), cfg.acc_width)
    assert len(dut.pixels) == cfg.pixels_width and len(dut.mask) == cfg.p
    assert len(dut.di_in) == cfg.di_width and len(dut.i0_in) == cfg.i_width
    levels = {i: 0 for i in cfg.network.shifts}
    operands = {}
    for adder in cfg.network.adders:
        levels[adder.target] = adder.level
        operands[adder.target] = (adder.a, adder.b, adder.subtract)
    for i in range(1, cfg.p + 1):
        block = dut.g_mult[i]
        level = int(block.LEVEL.value)
        add_y, sub_y = int(block.ADD_Y.value), int(block.SUB_Y.value)
        assert level == levels[i], (i, level, levels[i])
        if level:
            got = (i - add_y, add_y, False) if add_y else (i + sub_y, sub_y, True)
            assert got == operands[i], (i, got, operands[i])
    await tb.reset()
    tb.monitor.finish("structure")


@cocotb.test()
async def test_random_lines(dut):
    """Random lines (printed seed): ramps with divider increments, small and any increments;
    loads before the start, loads in the start cycle (old values run), back-to-back starts
    (the first three lines take one way each, whatever the seed; the vector soak carries the
    bulk random checking)."""
    tb = GouraudTB(dut)
    await tb.reset()
    rng = bench_rng("random")
    for i in range(RANDOM_LINES):
        i0, di, length = tb.random_line(rng)
        mode = (0.0, 0.8, 0.9)[i] if i < 3 else rng.random()
        if mode < 0.7:
            await tb.line(i0, di, length)
        elif mode < 0.85:
            # Write and start in the same cycle: the previous operands run, these land after.
            tb.drive_operands(i0=i0, di=di, len=length)
            await tb.start()
            tb.release_strobes()
            await tb.monitor.wait_idle()
        else:
            await tb.load(i0=i0, di=di, len=length)
            await tb.start()
            await tb.start_when_ready()  # the same line again, back to back
            await tb.monitor.wait_idle()
    stats = tb.monitor.finish("random_lines")
    assert stats.jobs_completed >= RANDOM_LINES and stats.back_to_back > 0, stats


@cocotb.test()
async def test_directed_extremes(dut):
    """Lengths 1, P-1, P, P+1, 2P, 2P+1 and the maximum; dI 0, +-1 LSB, +-1/3, the largest
    magnitudes; I0 at 0, in the middle and at the top; saturation at both ends."""
    tb = GouraudTB(dut)
    await tb.reset()
    cfg = tb.cfg
    i_lo, i_hi = cfg.i0_range
    d_lo, d_hi = cfg.di_range
    mid = (i_hi + 1) // 2
    count = 0
    for length in tb.directed_lengths():
        for di in tb.directed_increments():
            for i0 in (i_lo, mid, i_hi):
                await tb.line(i0, di, length)
                count += 1
    # The longest line: flat, +-1 LSB, full ramps both ways (divider increments, overshooting
    # into saturation), and the largest increments saturating at once at both ends.
    n = cfg.len_max
    longest = [
        (i_lo, 0, n),
        (i_hi, 0, n),
        (i_lo, 1, n),
        (i_hi, -1, n),
        (i_lo, tb.ramp_increment(i_lo, i_hi, n), n),
        (i_hi, tb.ramp_increment(i_hi, i_lo, n), n),
        (i_hi, d_hi, n),
        (i_lo, d_lo, n),
    ]
    for i0, di, length in longest:
        await tb.line(i0, di, length)
        count += 1
    stats = tb.monitor.finish("directed_extremes")
    assert stats.jobs_completed == count, stats


@cocotb.test()
async def test_length_zero(dut):
    """len = 0: one empty segment (mask 0, last 1) after one busy cycle, lanes computed."""
    tb = GouraudTB(dut)
    await tb.reset()
    rng = bench_rng("zero")
    tb.monitor.keep_results = True
    await tb.start()  # after reset every register is 0: a length-0 line of I0 = 0, dI = 0
    await tb.monitor.wait_idle()
    for _ in range(5):
        await tb.line(rng.randint(*tb.cfg.i0_range), rng.randint(*tb.cfg.di_range), 0)
    jobs = tb.monitor.result_log  # per job, the outputs the RTL gave at each valid
    # What the RTL put out, checked against the documented behaviour (not only the model):
    assert [len(outputs) for outputs in jobs] == [1] * 6, jobs
    assert [(o[0]["mask"], o[0]["last"]) for o in jobs] == [(0, 1)] * 6, jobs
    assert jobs[0][0]["pixels"] == 0, jobs
    stats = tb.monitor.finish("length_zero")
    assert stats.jobs_completed == 6


@cocotb.test()
async def test_writes_and_start_ignored_while_busy(dut):
    """Rule 1: operand writes and start pulses during a line change nothing."""
    tb = GouraudTB(dut)
    await tb.reset()
    rng = bench_rng("busy")
    cfg = tb.cfg
    for n in range(BUSY_LINES):
        i0, di, _ = tb.random_line(rng)
        length = cfg.len_max if n == 0 else rng.randint(1, 4 * cfg.p + 3)
        await tb.load(i0=i0, di=di, len=length)
        await tb.start()
        await tb.hammer_while_busy(
            gouraud.cycles(length, cfg),
            lambda: {
                "i0": rng.randint(*cfg.i0_range),
                "di": rng.randint(*cfg.di_range),
                "len": rng.randint(0, cfg.len_max),
            },
        )
    stats = tb.monitor.finish("busy_ignored")
    assert stats.writes_ignored > 0 and stats.starts_ignored > 0, stats


@cocotb.test()
async def test_back_to_back(dut):
    """Rule 3: a start in the first cycle busy is 0 is accepted (short and long lines)."""
    tb = GouraudTB(dut)
    await tb.reset()
    rng = bench_rng("b2b")
    for length in (1, tb.cfg.p, tb.cfg.p + 1, 3 * tb.cfg.p + 1):
        i0, di, _ = tb.random_line(rng)
        await tb.load(i0=i0, di=di, len=length)
        await tb.start()
        for _ in range(BACK_TO_BACK // 4):
            await tb.start_when_ready()
        await tb.monitor.wait_idle()
    stats = tb.monitor.finish("back_to_back")
    assert stats.back_to_back == 4 * (BACK_TO_BACK // 4), stats


@cocotb.test()
async def test_reset_mid_line(dut):
    """Rule 4: rst_n low during a line aborts it; registers are cleared (a start right after
    runs the empty line of length 0 from I0 = 0)."""
    tb = GouraudTB(dut)
    await tb.reset()
    rng = bench_rng("reset")
    cfg = tb.cfg
    for _ in range(RESETS):
        i0, di, _ = tb.random_line(rng)
        length = rng.randint(2 * cfg.p + 1, 6 * cfg.p)
        await tb.load(i0=i0, di=di, len=length)
        await tb.start()
        await tb.cycles(rng.randint(0, gouraud.cycles(length, cfg) - 2))
        await tb.reset(cycles=rng.randint(1, 3))
        await tb.start()
        await tb.monitor.wait_idle()
    stats = tb.monitor.finish("reset_mid_line")
    assert stats.jobs_aborted >= RESETS, stats


@cocotb.test()
async def test_mismatch_report_reproduces(dut):
    """Rule 6: the scoreboard flags a wrong segment and names the inputs that reproduce it."""
    tb = GouraudTB(dut)
    # Lane 1's low bit, in the last segment.
    tb.monitor.corrupt_model(-1, "pixels", lambda word: word ^ (1 << tb.cfg.i_int))
    await tb.reset()
    length = tb.cfg.p + 1
    await tb.line(5 << tb.cfg.i_frac, 3 << (tb.cfg.i_frac - 1), length)
    errors = tb.monitor.stats.errors
    operands = f"i0={5 << tb.cfg.i_frac}, di={3 << (tb.cfg.i_frac - 1)}, len={length}"
    assert len(errors) == 1 and operands in errors[0], errors
    # The reported inputs reproduce the RTL's word with the model directly.
    expected = gouraud.unit_results(5 << tb.cfg.i_frac, 3 << (tb.cfg.i_frac - 1), length, tb.cfg)
    assert f"'pixels': {expected[-1]['pixels']}" in errors[0], errors[0]
    errors.clear()
    tb.monitor.finish("mismatch_report")


@cocotb.test()
async def test_random_strobes(dut):
    """Rules 1-7 under the soak's stimulus: random strobes, start timing and resets, writes in
    start and busy cycles, values across 0 and at the extremes; every output, every cycle."""
    await random_strobes(GouraudTB(dut))
