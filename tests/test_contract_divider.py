# SPDX-License-Identifier: Apache-2.0
"""Contract sentences of the shift-add divider (docs/divider.md) that no other test checked.

Each test names the sentence it holds the model (or the benches' expectation) to; the table in
docs/divider.md points every sentence of the contract at its test.
"""

from __future__ import annotations

import dataclasses
import random
import re
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from model.units import divider
from model.units.divider import DEFAULT, DividerConfig
from sim import soak, units
from sim.runner import unit_parameters
from tests.contract_protocol import Drive, column, ones

CONFIGS = list(divider.ROM_CONFIGS.items())
IDS = [name for name, _ in CONFIGS]


def exact_reciprocal(k: int, n: int) -> int:
    """round(2^N / k), ties up, with exact rationals."""
    return int(Fraction(2**n, k) + Fraction(1, 2))


def ctz(x: int) -> int:
    return (x & -x).bit_length() - 1


# ------------------------------------------------------------------------ formats
def test_default_formats_are_the_documented_ones() -> None:
    """Formats table: a signed 21 bits (the difference of two Q8.12 intensities), k unsigned
    11 bits (scan lines up to 2047 pixels), r RECIP_BITS + 1 bits, q signed A_WIDTH + RECIP_BITS
    bits with RECIP_BITS fraction bits; one frozen config dataclass."""
    assert (DEFAULT.a_width, DEFAULT.k_width, DEFAULT.recip_bits) == (21, 11, 20)
    assert DEFAULT.a_range == (-(1 << 20), (1 << 20) - 1)
    q8_12_max = (256 << 12) - 1  # the largest Q8.12 intensity
    assert DEFAULT.a_range[0] <= -q8_12_max and q8_12_max <= DEFAULT.a_range[1]
    assert DEFAULT.k_max == 2047
    assert DEFAULT.recip_width == 21 and DEFAULT.q_width == 41 and DEFAULT.q_frac_bits == 20
    for _, cfg in CONFIGS:
        assert cfg.recip_width == cfg.recip_bits + 1
        assert cfg.q_width == cfg.a_width + cfg.recip_bits and cfg.q_frac_bits == cfg.recip_bits
        # k = 1 needs the 2^0 term: r = 2^N takes all N + 1 bits.
        assert divider.reciprocal(1, cfg.recip_bits) == 1 << cfg.recip_bits
    assert dataclasses.is_dataclass(DividerConfig)
    with pytest.raises(dataclasses.FrozenInstanceError):
        DEFAULT.a_width = 8  # type: ignore[misc]


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_ports_and_parameters_are_the_documented_ones(name: str, cfg: DividerConfig) -> None:
    """Ports table and "Parameters": the widths the benches build and check the RTL's ports
    against (ProtocolMonitor refuses an RTL whose port widths differ), the parameter names (the
    config fields in upper case) and the ROM image's name."""
    spec = units.spec(cfg)
    ops = {p.name: (p.width, p.signed) for p in spec.operands}
    assert ops == {"a": (cfg.a_width, True), "k": (cfg.k_width, False)}
    outs = {p.name: (p.width, p.signed, p.kind) for p in spec.outputs}
    assert outs == {
        "q": (cfg.a_width + cfg.recip_bits, True, "data"),
        "div_zero": (1, False, "flag"),
    }
    params = unit_parameters(cfg)
    assert set(params) == {"A_WIDTH", "K_WIDTH", "RECIP_BITS", "ROM_FILE"}
    assert (params["A_WIDTH"], params["K_WIDTH"], params["RECIP_BITS"]) == (
        cfg.a_width,
        cfg.k_width,
        cfg.recip_bits,
    )
    rom = divider.rom_path(cfg)
    assert rom.name == f"divider_recip_k{cfg.k_width}_n{cfg.recip_bits}.hex"
    assert rom.parent.name == "rom" and rom.parent.parent.name == "rtl"
    assert params["ROM_FILE"] == str(rom) and rom.exists()


# ------------------------------------------------------------------------ the arithmetic
def test_the_only_tie_is_outside_every_legal_range() -> None:
    """round(2^N / k) rounds ties up; the only tie is k = 2^(N+1), which no configuration
    accepts (K_WIDTH <= RECIP_BITS + 1, so k <= 2^(N+1) - 1; one bit more is refused)."""
    for n in range(1, 13):
        ties = [k for k in range(1, 1 << (n + 3)) if Fraction(2**n, k) % 1 == Fraction(1, 2)]
        assert ties == [1 << (n + 1)], n
        assert divider.reciprocal(1 << (n + 1), n) == 1  # 1/2 rounded up
        widest = DividerConfig(a_width=8, k_width=n + 1, recip_bits=n)
        assert widest.k_max == (1 << (n + 1)) - 1
        with pytest.raises(ValueError, match=f"k_width = {n + 2} is out of range"):
            DividerConfig(a_width=8, k_width=n + 2, recip_bits=n)


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_shift_add_steps_lose_no_bit(name: str, cfg: DividerConfig) -> None:
    """The shift register (the dividend with N extra fraction bits) shifted right once per
    step, added where the reciprocal bit (2^0 term first) is 1: every shifted copy is exact,
    so the quotient is exactly a * r in units of 2^-N."""
    rng = np.random.default_rng(11)
    lo, hi = cfg.a_range
    n = cfg.recip_bits
    for a, k in zip(
        rng.integers(lo, hi + 1, 300), rng.integers(1, cfg.k_max + 1, 300), strict=True
    ):
        a, k = int(a), int(k)
        shift_reg = a << n
        acc = 0
        for j in divider.reciprocal_terms(k, n):  # the set bits of r, MSB (2^0) first
            assert (shift_reg >> j) << j == shift_reg  # no bit shifted out
            acc += shift_reg >> j
        assert acc == a * exact_reciprocal(k, n) == divider.divide(a, k, cfg), (a, k)


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_error_is_at_most_half_an_lsb_of_the_reciprocal(name: str, cfg: DividerConfig) -> None:
    """Contract: "Its only error is that of r itself (at most abs(a) / 2^(N+1))", in every
    configuration whose ROM is committed: 2 abs(q k - a 2^N) <= abs(a) k, exact integers."""
    rng = np.random.default_rng(12)
    lo, hi = cfg.a_range
    a = np.concatenate([[lo, hi, -1, 1], rng.integers(lo, hi + 1, 3000)])
    k = np.concatenate([[cfg.k_max, cfg.k_max, 3, 3], rng.integers(1, cfg.k_max + 1, 3000)])
    q = divider.divide(a, k, cfg)
    n = cfg.recip_bits
    for qi, ai, ki in zip(q.tolist(), a.tolist(), k.tolist(), strict=True):
        assert 2 * abs(qi * ki - (ai << n)) <= abs(ai) * ki, (ai, ki)


def test_why_n_is_20_figures() -> None:
    """Contract: "an increment accumulated over the k pixels of a line ends within 255 * 2047 /
    2^21 = 0.25 of an 8-bit level ... (N = 19 leaves no margin: 0.498 levels; N = 11 drifts 85
    levels)": the N = 20 and N = 19 figures are the bound 255 * 2047 / 2^(N+1); 85 is the
    measured worst of N = 11 (its bound would be 127)."""
    ks = np.arange(1, 2048)

    def measured(n: int) -> float:
        r = divider.reciprocal(ks, n)
        return float((255 * np.abs(ks * r - 2**n) / 2**n).max())

    for n in (20, 19, 11):
        assert measured(n) <= 255 * 2047 / 2 ** (n + 1)  # |k r - 2^N| <= k/2
    assert round(255 * 2047 / 2**21, 2) == 0.25 and measured(20) <= 0.25
    assert round(255 * 2047 / 2**20, 3) == 0.498
    assert round(measured(11)) == 85


# ------------------------------------------------------------------------ timing
@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_cycles_are_n_plus_1_minus_ctz_of_the_rom_word(name: str, cfg: DividerConfig) -> None:
    """busy is high for cycles(k) = N + 1 - ctz(r) cycles (1 for k = 0 and k = 1; at most
    N + 1), for every k of every configuration; r computed here with exact rationals."""
    n = cfg.recip_bits
    ks = np.arange(0, cfg.k_max + 1)
    got = divider.cycles(ks, cfg)
    assert got[0] == 1 and got[1] == 1
    for k in range(1, cfg.k_max + 1):
        r = exact_reciprocal(k, n)
        assert got[k] == n + 1 - ctz(r), k
    assert got.max() <= n + 1


def test_exact_divider_takes_41_cycles_for_every_k() -> None:
    """The exact restoring divider (divide_exact) needs A_WIDTH + RECIP_BITS = 41 cycles for
    every k: one per quotient bit, whatever k is."""
    assert divider.cycles_exact(DEFAULT) == DEFAULT.a_width + DEFAULT.recip_bits == 41
    for _, cfg in CONFIGS:
        assert divider.cycles_exact(cfg) == cfg.q_width


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_bench_expects_busy_for_cycles_then_valid_with_busy_low(
    name: str, cfg: DividerConfig
) -> None:
    """Contract: "busy is high for cycles(k) cycles; valid is high in the next cycle, together
    with busy = 0" (one valid per division), and k = 0 gives div_zero = 1 with q = 0: what every
    cocotb test and the soak hold the RTL to, cycle by cycle."""
    lo, hi = cfg.a_range
    for k in sorted({0, 1, 2, 3, 5, 7, cfg.k_max - 1, cfg.k_max}):
        for a in (lo, -1, 0, hi):
            d = Drive(cfg)
            d.reset()
            after = d.job(a=a, k=k)
            c = divider.cycles(k, cfg)
            assert column(after, "busy") == [1] * c + [0] * (len(after) - c), (a, k)
            assert ones(column(after, "valid")) == [c], (a, k)
            result = after[c]
            if k == 0:
                assert (result["q"], result["div_zero"]) == (0, 1)
            else:
                assert (result["q"], result["div_zero"]) == (divider.divide(a, k, cfg), 0)


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_bench_expects_one_division_every_cycles_plus_one(name: str, cfg: DividerConfig) -> None:
    """Contract: "a new start is accepted in that cycle: one division every cycles(k) + 1
    clocks": start held high from the first division on, the benches expect a result every
    cycles(k) + 1 edges and every start after the first counted as back to back."""
    for k in (1, 3, cfg.k_max):
        d = Drive(cfg)
        d.reset()
        d.edge(a=5, k=k)
        first = len(d.outputs)
        for _ in range(6 * (divider.cycles(k, cfg) + 1)):
            d.edge(start=1)
        period = divider.cycles(k, cfg) + 1
        valids = ones(column(d.outputs[first:], "valid"))
        assert valids == [period * j + period - 1 for j in range(6)], (k, valids)
        assert d.model.stats.back_to_back == 5


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_bench_expects_reset_to_abort_and_clear(name: str, cfg: DividerConfig) -> None:
    """Reset aborts cleanly: busy, valid and div_zero 0 (q undefined until the next result),
    and the operand registers are cleared: a start right after reset divides 0 by 0."""
    d = Drive(cfg)
    d.reset()
    d.edge(a=cfg.a_range[1], k=3)
    d.edge(start=1)
    d.edge()
    out = d.edge(rst_n=0)
    assert (out["busy"], out["valid"], out["div_zero"], out["q"]) == (0, 0, 0, None)
    assert d.model.stats.jobs_aborted == 1
    after = d.job()
    assert d.model.last_job.operands == {"a": 0, "k": 0}
    assert (after[1]["q"], after[1]["div_zero"]) == (0, 1)


def test_bench_expects_results_held_between_divisions() -> None:
    """Contract: "q ... held until the next result" and div_zero "the last division had k = 0":
    both outputs keep the last division's values in every cycle until the next result."""
    d = Drive(DEFAULT)
    d.reset()
    first = d.job(tail=10, a=-7, k=0)
    assert all((o["q"], o["div_zero"]) == (0, 1) for o in first[1:])
    second = d.job(tail=0, a=100, k=4)
    c = divider.cycles(4)
    assert all((o["q"], o["div_zero"]) == (0, 1) for o in second[:c])  # still the last result
    assert (second[c]["q"], second[c]["div_zero"]) == (100 << 18, 0)


# ------------------------------------------------------------------------ the soak
def test_soak_stimulus_replays_from_its_seed_and_reaches_the_extremes() -> None:
    """Contract: "The seed is printed in the run's summary; SOAK_SEED=N make sim replays it": the
    soak's stimulus is a function of its seed; it writes the extremes and values across 0, in
    start and busy cycles, with random resets."""
    cfg = DEFAULT
    stim = soak.stimulus(cfg, 20_000, seed=1234)
    assert stim == soak.stimulus(cfg, 20_000, seed=1234)
    assert stim != soak.stimulus(cfg, 20_000, seed=1235)
    lo, hi = cfg.a_range
    written_a = {s["a_in"] for s in stim if s["a_we"]}
    written_k = {s["k_in"] for s in stim if s["k_we"]}
    assert {lo, -1, 0, 1, hi} <= written_a
    assert {0, 1, cfg.k_max} <= written_k
    stats = soak.predict(cfg, stim).stats
    assert stats.writes_at_start > 0 and stats.writes_ignored > 0 and stats.starts_ignored > 0
    assert stats.jobs_aborted > 0 and stats.back_to_back > 0


def test_soak_seed_comes_from_the_environment(monkeypatch) -> None:
    """SOAK_SEED=N is the seed the soak runs with (tests/test_soak.py reads it)."""
    from tests.test_soak import soak_seed

    seed = random.Random(3).randrange(1 << 31)
    monkeypatch.setenv("SOAK_SEED", str(seed))
    assert soak_seed() == seed


# ------------------------------------------------------------------------ RTL parameters, reset
RTL_FILE = Path(__file__).resolve().parent.parent / "rtl" / "divider_shift.v"


def rtl_parameters() -> dict[str, str]:
    """The parameters the RTL's module header declares, in order, with their default text."""
    header = RTL_FILE.read_text().split("module divider_shift #(", 1)[1].split("\n) (", 1)[0]
    return dict(re.findall(r"^\s*parameter\s+(\w+)\s*=\s*(.+?),?\s*$", header, flags=re.M))


def test_rtl_parameters_are_the_documented_ones() -> None:
    """Parameters: the config fields in UPPER_CASE with the defaults of ``DEFAULT``, ROM_FILE
    (default: the default configuration's image in the folder `SHADING_ROM_DIR), and last
    RESET_ALL, default 0 (docs/fpga.md, "Reset"), which no model field maps to."""
    params = rtl_parameters()
    assert list(params) == ["A_WIDTH", "K_WIDTH", "RECIP_BITS", "ROM_FILE", "RESET_ALL"]
    assert params["RESET_ALL"] == "0"
    for field in ("a_width", "k_width", "recip_bits"):
        assert params[field.upper()] == str(getattr(DEFAULT, field)), field
    assert set(unit_parameters(DEFAULT)) | {"RESET_ALL"} == set(params)
    assert params["ROM_FILE"] == '{`SHADING_ROM_DIR, "/divider_recip_k11_n20.hex"}'
    assert divider.rom_path(DEFAULT).name == "divider_recip_k11_n20.hex"


@pytest.mark.parametrize("reset_all", [0, 1])
def test_bench_expects_the_data_outputs_reset_only_with_reset_all(reset_all: int) -> None:
    """Reset: busy, valid and div_zero are 0 after a reset whatever RESET_ALL; q is undefined
    until the next result with RESET_ALL = 0 (a don't-care: the data path is not reset, Icarus
    shows X) and 0 with RESET_ALL = 1 (every register reset).  The runner builds the RTL with
    the bench's RESET_ALL and tells the monitor (BENCH_RESET_ALL)."""
    d = Drive(DEFAULT)
    d.model.reset_all = bool(reset_all)
    d.reset()
    assert d.outputs[-1]["q"] == (0 if reset_all else None)
    d.job(a=100, k=4)
    out = d.edge(rst_n=0)
    assert (out["busy"], out["valid"], out["div_zero"]) == (0, 0, 0)
    assert out["q"] == (0 if reset_all else None)
