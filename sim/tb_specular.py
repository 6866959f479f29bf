# SPDX-License-Identifier: Apache-2.0
"""cocotb bench of rtl/specular_unit.v against model.specular (run by tests/test_sim_specular)."""

from __future__ import annotations

import random

import cocotb
import numpy as np
from cocotb.triggers import ReadOnly, RisingEdge

from model.units import specular
from model.units.specular import SpecularConfig
from sim.common import (
    ProtocolMonitor,
    UnitTB,
    bench_config,
    bench_rng,
    random_strobes,
)

# Lines of the every-n test that are long (the rest have l = 0..7, to keep the run short).
# The bulk random checking of the unit is the vector soak's (tests/test_soak.py
# ``test_soak_every_output_every_cycle``, sim/soak.py: 100 000 cycles of the default
# configuration, 20 000 of narrow and inflection), with no Python in the loop; the longest
# lines are also in test_extremes.
LONG_LINES = 3
INVALID_N = [0, 1001, 1002, 1023]


class SpecularTB(UnitTB):
    """Driver + scoreboard for one specular-unit configuration."""

    def __init__(self, dut) -> None:
        self.cfg = SpecularConfig(**bench_config())
        super().__init__(dut, ProtocolMonitor(dut, self.cfg))

    async def line(self, c: int, dz: int, z0: int, n: int, length: int) -> None:
        """One line: all operands in one cycle, start in the next, wait until busy falls."""
        await self.run(c=c, dz=dz, z0=z0, n=n, len=length)

    # ------------------------------------------------------------------ operand generators
    def scale(self, n: int) -> float:
        """a of n (1 for an n the unit refuses): the angle span where the highlight lives is 1/a."""
        if not specular.n_valid(n, self.cfg):
            return 1.0
        return specular.alpha_value(n, specular.decode_k(n, self.cfg), self.cfg.alpha)

    def z_reg(self, units: float) -> int:
        return int(self.cfg.z_format.quantise(units))

    def random_geometry(self, rng: random.Random, n: int, length: int) -> dict[str, int]:
        """Registers from ``setup_line`` for random end vectors around a common direction."""
        base = _unit(rng)
        spread = rng.choice([0.02, 0.1, 0.4, 1.5, 3.0])
        vecs = [_perturb(rng, base, spread) for _ in range(4)]
        if rng.random() < 0.1:
            vecs[1] = -vecs[0]  # N1 = -N2
        if rng.random() < 0.1:
            vecs[3] = vecs[2]  # gamma -> 0 when N1 = N2
            vecs[1] = vecs[0]
        light = rng.choice([1.0, rng.uniform(0.0, 1.3)])
        n_setup = n if specular.n_valid(n, self.cfg) else 1
        s = specular.setup_line(*vecs, n_setup, light, length, self.cfg)
        return {"c": s.c_reg, "dz": s.dz_reg, "z0": s.z0_reg, "n": n, "len": length}

    def random_registers(self, rng: random.Random, n: int, length: int) -> dict[str, int]:
        """Register values aimed at the highlight: the scaled angle sweeps about -1.3 .. 1.3."""
        span = 1.3 / self.scale(n)
        z_start = rng.uniform(-span, span)
        z_end = rng.uniform(-span, span)
        dz = (z_end - z_start) / max(length, 1)
        c = rng.choice([self.cfg.c_format.hi, rng.randint(0, self.cfg.c_format.hi)])
        return {"c": c, "dz": self.z_reg(dz), "z0": self.z_reg(z_start), "n": n, "len": length}

    def any_registers(self, rng: random.Random, n: int, length: int) -> dict[str, int]:
        lo, hi = self.cfg.z_format.lo, self.cfg.z_format.hi
        return {
            "c": rng.randint(0, self.cfg.c_format.hi),
            "dz": rng.randint(lo, hi),
            "z0": rng.randint(lo, hi),
            "n": n,
            "len": length,
        }

    def random_line(self, rng: random.Random, n: int, length: int) -> dict[str, int]:
        pick = rng.random()
        if pick < 0.45:
            return self.random_geometry(rng, n, length)
        if pick < 0.9:
            return self.random_registers(rng, n, length)
        return self.any_registers(rng, n, length)


def _unit(rng: random.Random) -> np.ndarray:
    while True:
        v = np.array([rng.gauss(0, 1) for _ in range(3)])
        if np.linalg.norm(v) > 1e-3:
            return v / np.linalg.norm(v)


def _perturb(rng: random.Random, v: np.ndarray, spread: float) -> np.ndarray:
    w = v + spread * _unit(rng) * rng.random()
    return w / np.linalg.norm(w) if np.linalg.norm(w) > 1e-6 else v


@cocotb.test(timeout_time=3, timeout_unit="ms")  # ~10x its cycles: a hung busy fails, not hangs
async def test_every_n_random_lines(dut):
    """Every n = 1..1000 once (plus invalid n), random operands, a few long lines (every n
    through the decoder and ROM 9 of the RTL; the bulk random lines are the vector soak's)."""
    tb = SpecularTB(dut)
    await tb.reset()
    rng = bench_rng("every_n")
    ns = list(range(1, specular.N_MAX + 1)) + INVALID_N
    rng.shuffle(ns)
    long_at = set(rng.sample(range(len(ns)), LONG_LINES))
    pixels = 0
    for i, n in enumerate(ns):
        if i in long_at:
            length = rng.randint(tb.cfg.len_max // 2, tb.cfg.len_max)
        else:
            length = rng.randint(0, min(7, tb.cfg.len_max))
        ops = tb.random_line(rng, n, length)
        await tb.line(ops["c"], ops["dz"], ops["z0"], ops["n"], ops["len"])
        pixels += length + 1
    stats = tb.monitor.finish("every_n_random_lines")
    assert stats.jobs_completed == len(ns), stats
    assert stats.results_compared == pixels, stats


@cocotb.test(timeout_time=500, timeout_unit="us")
async def test_fig11_four_results(dut):
    """The patent's fig. 11: l = 3 gives exactly four valid strobes, the first for the start."""
    tb = SpecularTB(dut)
    await tb.reset()
    ops = tb.random_registers(random.Random(11), 40, 3)
    await tb.line(ops["c"], ops["dz"], ops["z0"], ops["n"], 3)
    stats = tb.monitor.finish("fig11")
    assert stats.jobs_completed == 1 and stats.results_compared == 4, stats
    assert specular.valid_offsets(3, tb.cfg) == [specular.FILL_LATENCY + i for i in range(4)]


@cocotb.test(timeout_time=2, timeout_unit="ms")
async def test_extremes(dut):
    """n = 1 and 1000, l = 0 and the maximum, angles across 0 and pi/2, C = 0 and the maximum,
    the most negative and largest angle registers over the longest line (no wrap); a unit that
    keeps n_first..n_last also n_first - 1, n_first, n_last and n_last + 1."""
    tb = SpecularTB(dut)
    await tb.reset()
    cfg = tb.cfg
    c_max, lmax = cfg.c_format.hi, cfg.len_max
    z_lo, z_hi = cfg.z_format.lo, cfg.z_format.hi
    one = 1 << cfg.z_frac_bits  # pi/2
    cases = []
    kept = (
        {cfg.n_first - 1, cfg.n_first, cfg.n_last, cfg.n_last + 1} if cfg.rom9_depth < 1000 else ()
    )
    for n in sorted({1, 2, 3, 6, 7, 1000, *kept}):
        span = 1.0 / tb.scale(n)  # the angle where the scaled angle reaches pi/2
        edge = tb.z_reg(span)
        # Across zero: from -span/2 to +span/2 in 16 steps; across pi/2 in both directions.
        cases.append((c_max, tb.z_reg(span / 16), tb.z_reg(-span / 2), n, 16))
        cases.append((c_max, 1, edge - 8, n, 16))  # the last address steps before pi/2
        cases.append((c_max, -1, -edge + 8, n, 16))
        cases.append((c_max, tb.z_reg(2 * span / lmax), -edge, n, lmax))  # longest, through 0
        cases.append((c_max, 0, 0, n, 0))  # the peak, one pixel
        cases.append((0, 1 << 10, -(1 << 12), n, 5))  # C = 0
    cases += [
        (c_max, z_lo, z_lo, 1000, lmax),  # the accumulator's most negative value
        (c_max, z_hi, z_hi, 1000, lmax),  # ... and largest
        (c_max, z_hi, z_lo, 1, 3),
        (c_max, 0, z_lo, 1, 0),
        (c_max, 0, one, 1, 0),  # exactly pi/2
        (c_max, 0, -one, 1, 0),
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
    tb = SpecularTB(dut)
    await tb.reset()
    rng = bench_rng("busy")
    for _ in range(12):
        length = rng.randint(0, min(12, tb.cfg.len_max))
        ops = tb.random_line(rng, rng.randint(1, specular.N_MAX), length)
        await tb.load(**ops)
        await tb.start()
        await tb.hammer_while_busy(
            specular.cycles(length, tb.cfg),
            lambda: tb.any_registers(rng, rng.randint(0, 1023), rng.randint(0, tb.cfg.len_max)),
        )
    stats = tb.monitor.finish("busy_ignored")
    assert stats.writes_ignored > 0 and stats.starts_ignored > 0, stats


@cocotb.test(timeout_time=500, timeout_unit="us")
async def test_back_to_back(dut):
    """Rule 3: a start in the first cycle busy is 0 is accepted; the operands written in that
    same cycle are kept for the line after (the started line runs on the old ones)."""
    tb = SpecularTB(dut)
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
    tb = SpecularTB(dut)
    await tb.reset()
    rng = bench_rng("reset")
    for _ in range(10):
        length = rng.randint(0, min(20, tb.cfg.len_max))
        ops = tb.random_line(rng, rng.randint(1, specular.N_MAX), length)
        await tb.load(**ops)
        await tb.start()
        # tb.reset() waits one more edge before rst_n goes low, sampled one edge later: the
        # latest edge that still aborts is the one before busy falls.
        await tb.cycles(rng.randint(0, specular.cycles(length, tb.cfg) - 3))
        await tb.reset(cycles=rng.randint(1, 3))
        # Cleared registers: a start without loading is one pixel with n = 0 (n_err, 0).
        await tb.start()
        await tb.monitor.wait_idle()
    stats = tb.monitor.finish("reset_mid_line")
    assert stats.jobs_aborted >= 10, stats


@cocotb.test(timeout_time=500, timeout_unit="us")
async def test_mismatch_report_reproduces(dut):
    """Rule 6: the scoreboard flags a wrong result and names the inputs that reproduce it."""
    tb = SpecularTB(dut)
    tb.monitor.corrupt_model(2, "intensity", lambda v: v + 1)
    await tb.reset()
    c = tb.cfg.c_format.hi
    await tb.line(c, 1 << (tb.cfg.z_frac_bits - 8), -(1 << (tb.cfg.z_frac_bits - 6)), 50, 4)
    errors = tb.monitor.stats.errors
    assert len(errors) == 1 and "result 2 mismatch" in errors[0], errors
    assert f"c={c}, dz=" in errors[0] and "n=50, len=4" in errors[0], errors[0]
    # The reported inputs reproduce the RTL's value with the model directly.
    values, _ = specular.unit_line(
        c, 1 << (tb.cfg.z_frac_bits - 8), -(1 << (tb.cfg.z_frac_bits - 6)), 50, 4, tb.cfg
    )
    assert f"'intensity': {int(values[2])}," in errors[0], errors[0]
    errors.clear()
    tb.monitor.finish("mismatch_report")


@cocotb.test()
async def test_random_strobes(dut):
    """Rules 1-7 under the soak's stimulus: random strobes, start timing and resets, writes in
    start and busy cycles, values across 0 and at the extremes; every output, every cycle."""
    await random_strobes(SpecularTB(dut))


@cocotb.test()
async def test_rom9_and_decoder_read_on_the_n_write(dut):
    """ROM 9 and the decoder are read when n is written: right after an idle-cycle n write the
    working registers hold a = ROM 9 word n (address n - n_first; ROM 9's first word for an n
    the unit refuses: the zero gate discards it), the decoded table and n_err of the model."""
    tb = SpecularTB(dut)
    await tb.reset()
    cfg = tb.cfg
    words = specular.rom9_words(cfg)
    edges = {0, 1, 2, 3, 6, 7, 1000, 1001, 1023, *cfg.n_hi}
    edges |= {cfg.n_first - 1, cfg.n_first, cfg.n_last, cfg.n_last + 1}
    for n in sorted(edges | set(range(1, 1024, 37))):
        kept = specular.n_valid(n, cfg)
        await tb.load(n=n)
        await ReadOnly()
        want = int(words[n if kept else cfg.n_first])
        rom_q = dut.u_rom9.q_a_reg  # ROM 9's read register (the ROM module)
        assert rom_q.value.to_unsigned() == want, (n, rom_q.value)
        assert int(dut.nerr_reg.value) == int(not kept), n
        if kept:
            k = specular.decode_k(n, tb.cfg)
            assert tb.cfg.ks[dut.tsel_reg.value.to_unsigned()] == k, (n, k)
        await RisingEdge(dut.clk)
    tb.monitor.finish("rom9_and_decoder_read_on_the_n_write")
