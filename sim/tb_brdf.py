# SPDX-License-Identifier: Apache-2.0
"""cocotb bench of rtl/brdf_unit.v against model.units.brdf (run by tests/test_sim_brdf.py).

The configuration (a ``FixedConfig``, its form among ``brdf.RTL_FORMS``) comes from the runner
as JSON; the protocol monitor (sim/common.py ``ProtocolMonitor``, the unit's ports and job from
sim/units.py) compares every output in every cycle with the model: ``brdf.unit_line`` per job,
``brdf.cycles`` and ``brdf.valid_offsets`` for busy and valid.
"""

from __future__ import annotations

import math
import random

import cocotb
from cocotb.triggers import ReadOnly, RisingEdge

from model.units import brdf, specular
from model.units.brdf import FixedConfig
from model.units.specular import SpecularConfig
from sim.common import ProtocolMonitor, UnitTB, bench_config, bench_rng, random_strobes

# Lines of the every-n test that are long (the rest have l = 0..7, to keep the run short).
LONG_LINES = 3
INVALID_N = [0, 1001, 1002, 1023]


def config_from_json(fields: dict) -> FixedConfig:
    """The ``FixedConfig`` the runner passed (``dataclasses.asdict``: the angle as a dict)."""
    return FixedConfig(**{**fields, "angle": SpecularConfig(**fields["angle"])})


class BrdfTB(UnitTB):
    """Driver + scoreboard for one BRDF-unit configuration."""

    def __init__(self, dut) -> None:
        self.cfg = config_from_json(bench_config())
        self.fmt = self.cfg.angle
        super().__init__(dut, ProtocolMonitor(dut, self.cfg))

    async def line(self, c: int, dz: int, z0: int, n: int, length: int) -> None:
        """One line: all operands in one cycle, start in the next, wait until busy falls."""
        await self.run(c=c, dz=dz, z0=z0, n=n, len=length)

    # ------------------------------------------------------------------ operand generators
    def span(self, n: int) -> float:
        """The angle (units of pi/2) where the form's highlight ends: the epicentre of cos^n,
        or the cosine-quadratic's zero arccos(1 - 16/(7n)), or the log2 form's arccos(2^(-3/n))
        (n (-log2 cos) = 3), or where the piecewise form's bloom part c / (alpha - beta c)
        falls to 2^-8 (c = 2^-8 alpha / (1 + 2^-8 beta)), if that comes later; 1 for an n the
        unit refuses."""
        if not 1 <= n <= specular.N_MAX:
            return 1.0
        end = specular.epicentre(n)
        if self.cfg.form == "cosine_quadratic" and 7 * n > 8:
            end = max(end, math.acos(1.0 - 16.0 / (7.0 * n)))
        if self.cfg.form == "log2":
            end = max(end, math.acos(2.0 ** (-3.0 / n)))
        if self.cfg.form == "piecewise":
            bloom, level = brdf.bloom_coefficients(n), 2.0**-8
            end = max(end, math.acos(level * bloom.alpha / (1.0 + level * bloom.beta)))
        return min(1.0, end / (math.pi / 2))

    def z_reg(self, units: float) -> int:
        return int(self.fmt.z_format.quantise(units))

    def random_registers(self, rng: random.Random, n: int, length: int) -> dict[str, int]:
        """Registers aimed at the highlight: the angle sweeps about -1.5 .. 1.5 spans (for the
        piecewise form half the lines the epicentre's, where its cubic part works, half the
        bloom part's, many times wider)."""
        span = 1.5 * self.span(n)
        if self.cfg.form == "piecewise" and 1 <= n <= specular.N_MAX and rng.random() < 0.5:
            span = 1.5 * min(1.0, specular.epicentre(n) / (math.pi / 2))
        z_start = rng.uniform(-span, span)
        z_end = rng.uniform(-span, span)
        dz = (z_end - z_start) / max(length, 1)
        c = rng.choice([self.fmt.c_format.hi, rng.randint(0, self.fmt.c_format.hi)])
        return {"c": c, "dz": self.z_reg(dz), "z0": self.z_reg(z_start), "n": n, "len": length}

    def any_registers(self, rng: random.Random, n: int, length: int) -> dict[str, int]:
        lo, hi = self.fmt.z_format.lo, self.fmt.z_format.hi
        return {
            "c": rng.randint(0, self.fmt.c_format.hi),
            "dz": rng.randint(lo, hi),
            "z0": rng.randint(lo, hi),
            "n": n,
            "len": length,
        }

    def random_line(self, rng: random.Random, n: int, length: int) -> dict[str, int]:
        if rng.random() < 0.9:
            return self.random_registers(rng, n, length)
        return self.any_registers(rng, n, length)


@cocotb.test(timeout_time=3, timeout_unit="ms")  # ~10x its cycles: a hung busy fails, not hangs
async def test_every_n_random_lines(dut):
    """Every n = 1..1000 once (plus invalid n), random operands aimed at the highlight, a few
    long lines: every n through the unit's n register (and the coefficient table)."""
    tb = BrdfTB(dut)
    await tb.reset()
    rng = bench_rng("every_n")
    ns = list(range(1, specular.N_MAX + 1)) + INVALID_N
    rng.shuffle(ns)
    long_at = set(rng.sample(range(len(ns)), LONG_LINES))
    pixels = 0
    for i, n in enumerate(ns):
        if i in long_at:
            length = rng.randint(tb.fmt.len_max // 2, tb.fmt.len_max)
        else:
            length = rng.randint(0, min(7, tb.fmt.len_max))
        ops = tb.random_line(rng, n, length)
        await tb.line(ops["c"], ops["dz"], ops["z0"], ops["n"], ops["len"])
        pixels += length + 1
    stats = tb.monitor.finish("every_n_random_lines")
    assert stats.jobs_completed == len(ns), stats
    assert stats.results_compared == pixels, stats


@cocotb.test(timeout_time=2, timeout_unit="ms")
async def test_extremes(dut):
    """n = 1, 2, 3, 8 and 1000, l = 0 and the maximum, angles across 0, at and over pi/2 (every
    table address next to it), C = 0 and the maximum, the most negative and largest angle
    registers over the longest line (no wrap), invalid n."""
    tb = BrdfTB(dut)
    await tb.reset()
    fmt = tb.fmt
    c_max, lmax = fmt.c_format.hi, fmt.len_max
    z_lo, z_hi = fmt.z_format.lo, fmt.z_format.hi
    one = 1 << fmt.z_frac_bits  # pi/2
    half_step = 1 << max(0, tb.cfg.addr_shift - 1)  # half an angle-table address step
    cases = []
    for n in (1, 2, 3, 8, 1000):
        edge = tb.z_reg(tb.span(n))
        cases.append((c_max, tb.z_reg(tb.span(n) / 8), -edge, n, 16))  # across zero
        cases.append((c_max, half_step, one - 8 * half_step, n, 16))  # up to and past pi/2
        cases.append((c_max, -half_step, -one + 8 * half_step, n, 16))
        cases.append((c_max, tb.z_reg(2 * tb.span(n) / lmax), -edge, n, lmax))  # longest
        cases.append((c_max, 0, 0, n, 0))  # the peak, one pixel
        cases.append((0, 1 << 10, -(1 << 12), n, 5))  # C = 0
    cases += [
        (c_max, z_lo, z_lo, 1000, lmax),  # the accumulator's most negative value
        (c_max, z_hi, z_hi, 1000, lmax),  # ... and largest
        (c_max, z_hi, z_lo, 1, 3),
        (c_max, 0, one, 1, 0),  # exactly pi/2
        (c_max, 0, -one, 1, 0),
        (c_max, 0, one - half_step, 2, 0),  # rounds up to pi/2
        (c_max, 0, one - half_step - 1, 2, 0),  # the last address before it
        (c_max, 0, 0, 1001, 4),  # invalid n: zeros with n_err
        (c_max, 0, 0, 0, 0),
    ]
    pixels = 0
    for c, dz, z0, n, length in cases:
        await tb.line(c, max(z_lo, min(z_hi, dz)), max(z_lo, min(z_hi, z0)), n, length)
        pixels += length + 1
    stats = tb.monitor.finish("extremes")
    assert stats.results_compared == pixels, stats


@cocotb.test(timeout_time=500, timeout_unit="us")
async def test_writes_and_start_ignored_while_busy(dut):
    """Rule 1: operand writes and start pulses during a line change nothing."""
    tb = BrdfTB(dut)
    await tb.reset()
    rng = bench_rng("busy")
    for _ in range(12):
        length = rng.randint(0, min(12, tb.fmt.len_max))
        ops = tb.random_line(rng, rng.randint(1, specular.N_MAX), length)
        await tb.load(**ops)
        await tb.start()
        await tb.hammer_while_busy(
            brdf.cycles(length, tb.cfg),
            lambda: tb.any_registers(rng, rng.randint(0, 1023), rng.randint(0, tb.fmt.len_max)),
        )
    stats = tb.monitor.finish("busy_ignored")
    assert stats.writes_ignored > 0 and stats.starts_ignored > 0, stats


@cocotb.test(timeout_time=500, timeout_unit="us")
async def test_back_to_back(dut):
    """Rule 3: a start in the first cycle busy is 0 is accepted; the operands written in that
    same cycle are kept for the line after (the started line runs on the old ones)."""
    tb = BrdfTB(dut)
    await tb.reset()
    rng = bench_rng("b2b")
    ops = tb.random_line(rng, rng.randint(1, specular.N_MAX), rng.randint(0, 6))
    await tb.load(**ops)
    await tb.start()
    for _ in range(25):
        nxt = tb.random_line(rng, rng.randint(1, specular.N_MAX), rng.randint(0, 6))
        tb.drive_operands(**nxt)  # ignored while busy, lands with the accepted start
        await tb.start_when_ready()
        tb.release_strobes()
    await tb.monitor.wait_idle()
    stats = tb.monitor.finish("back_to_back")
    assert stats.back_to_back == 25, stats


@cocotb.test(timeout_time=500, timeout_unit="us")
async def test_reset_mid_line(dut):
    """Rule 4: rst_n low during a line (also during the pipeline fill) aborts it cleanly."""
    tb = BrdfTB(dut)
    await tb.reset()
    rng = bench_rng("reset")
    for _ in range(10):
        length = rng.randint(0, min(20, tb.fmt.len_max))
        ops = tb.random_line(rng, rng.randint(1, specular.N_MAX), length)
        await tb.load(**ops)
        await tb.start()
        # tb.reset() waits one more edge before rst_n goes low, sampled one edge later: the
        # latest edge that still aborts is the one before busy falls.
        await tb.cycles(rng.randint(0, brdf.cycles(length, tb.cfg) - 3))
        await tb.reset(cycles=rng.randint(1, 3))
        # Cleared registers: a start without loading is one pixel with n = 0 (n_err, 0).
        await tb.start()
        await tb.monitor.wait_idle()
    stats = tb.monitor.finish("reset_mid_line")
    assert stats.jobs_aborted >= 10, stats


@cocotb.test(timeout_time=500, timeout_unit="us")
async def test_mismatch_report_reproduces(dut):
    """Rule 6: the scoreboard flags a wrong result and names the inputs that reproduce it."""
    tb = BrdfTB(dut)
    tb.monitor.corrupt_model(2, "intensity", lambda v: v + 1)
    await tb.reset()
    c, zf = tb.fmt.c_format.hi, tb.fmt.z_frac_bits
    dz, z0 = 1 << (zf - 8), -(1 << (zf - 6))
    await tb.line(c, dz, z0, 50, 4)
    errors = tb.monitor.stats.errors
    assert len(errors) == 1 and "result 2 mismatch" in errors[0], errors
    assert f"c={c}, dz={dz}, z0={z0}, n=50, len=4" in errors[0], errors[0]
    # The reported inputs reproduce the RTL's value with the model directly.
    values, _ = brdf.unit_line(c, dz, z0, 50, 4, tb.cfg)
    assert f"'intensity': {int(values[2])}," in errors[0], errors[0]
    errors.clear()
    tb.monitor.finish("mismatch_report")


@cocotb.test()
async def test_random_strobes(dut):
    """Rules 1-7 under the soak's stimulus: random strobes, start timing and resets, writes in
    start and busy cycles, values across 0 and at the extremes; every output, every cycle."""
    await random_strobes(BrdfTB(dut))


@cocotb.test()
async def test_n_register_read_on_the_n_write(dut):
    """What the unit keeps of n is taken when n is written: right after an idle-cycle n write
    the coefficient table's read register holds the model's word of n (address n - 1; word 0
    for an n the unit refuses; the cubic's and the piecewise form's two words of n, 2 (n - 1)
    and 2 (n - 1) + 1, on the ROM's two ports), or the cosine-quadratic's register 7n, the log2
    form's register n;
    nerr_reg the n error."""
    tb = BrdfTB(dut)
    await tb.reset()
    cfg = tb.cfg
    words = brdf.rom_words(cfg, "coef") if cfg.coefficients else None
    for n in sorted({0, 1, 2, 3, 999, 1000, 1001, 1023, *range(1, 1024, 37)}):
        ok = 1 <= n <= specular.N_MAX
        await tb.load(n=n)
        await ReadOnly()
        i = n - 1 if ok else 0
        if cfg.form in ("cubic", "piecewise"):
            rom = getattr(dut, f"g_coef_rom_{cfg.form}").u_coef_rom
            want = (int(words[2 * i]), int(words[2 * i + 1]))
            got = (rom.q_a_reg.value.to_unsigned(), rom.g_port_b.q_b_reg.value.to_unsigned())
        elif words is not None:
            want = int(words[i])
            got = dut.g_coef_rom.u_coef_rom.q_a_reg.value.to_unsigned()
        elif cfg.form == "log2":
            want, got = n, dut.g_n_word.k_reg.value.to_unsigned()
        else:
            want, got = 7 * n, dut.g_seven_n.k_reg.value.to_unsigned()
        assert got == want, (n, got, want)
        assert int(dut.nerr_reg.value) == int(not ok), n
        await RisingEdge(dut.clk)
    tb.monitor.finish("n_register_read_on_the_n_write")
