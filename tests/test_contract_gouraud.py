# SPDX-License-Identifier: Apache-2.0
"""Contract sentences of the segment Gouraud unit (docs/gouraud.md) that no other test checked.

Each test names the sentence it holds the model (or the benches' expectation) to; the table in
docs/gouraud.md points every sentence of the contract at its test.
"""

from __future__ import annotations

import dataclasses
import itertools
import re
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from model.units import fixed, gouraud
from model.units.gouraud import DEFAULT, GouraudConfig
from sim import soak, units
from sim.runner import unit_parameters
from tests.contract_protocol import Drive, column, ones

# The benches' configurations (tests/test_sim_gouraud.py, tests/test_soak.py).
BENCH_CONFIGS = {f"p{p}_f{f}": GouraudConfig(p=p, i_frac=f) for p in (2, 4, 8) for f in (12, 4)}
BENCH_CONFIGS["p16_f12"] = GouraudConfig(p=16, i_frac=12)
CONFIGS = list(BENCH_CONFIGS.items())
IDS = [name for name, _ in CONFIGS]


# ------------------------------------------------------------------------ formats
def test_default_formats_are_the_documented_ones() -> None:
    """Formats table, defaults: i0 unsigned Q8.12 (0 .. 256 - 2^-12), di signed Q9.12
    (-256 .. 256 - 2^-12, so a one-pixel step of +-255 fits), len 11 bits (1..2047), output
    pixel 8 bits (0..255), start register 33 bits; one frozen config dataclass."""
    one = 1 << 12
    assert DEFAULT.i0_range == (0, 256 * one - 1)
    assert DEFAULT.di_range == (-256 * one, 256 * one - 1)
    assert DEFAULT.di_range[0] <= -255 * one and 255 * one <= DEFAULT.di_range[1]
    assert (DEFAULT.len_width, DEFAULT.len_max, DEFAULT.out_max) == (11, 2047, 255)
    assert DEFAULT.acc_width == 33
    assert dataclasses.is_dataclass(GouraudConfig)
    with pytest.raises(dataclasses.FrozenInstanceError):
        DEFAULT.p = 4  # type: ignore[misc]


def test_internal_widths_are_the_documented_formulas() -> None:
    """Contract: "start register, lane adders: signed LEN_WIDTH + I_INT + I_FRAC + 1 bits, +1
    when I_INT + I_FRAC >= LEN_WIDTH"; "multiples i*dI, i <= P: signed I_INT + I_FRAC + 1 + log2
    P bits", and no multiple of an extreme increment wraps in that width."""
    for p, i_int, i_frac in itertools.product(gouraud.LANE_COUNTS, (1, 4, 8, 16), (1, 4, 12, 24)):
        log2p = p.bit_length() - 1
        for len_width in range(log2p + 1, 17):
            cfg = GouraudConfig(i_int=i_int, i_frac=i_frac, p=p, len_width=len_width)
            extra = 1 if i_int + i_frac >= len_width else 0
            assert cfg.acc_width == len_width + i_int + i_frac + 1 + extra, cfg
        assert cfg.inc_width == i_int + i_frac + 1 + log2p
        m_lo, m_hi = fixed.signed_range(cfg.inc_width)
        d_lo, d_hi = cfg.di_range
        assert all(m_lo <= i * d_lo and i * d_hi <= m_hi for i in range(1, p + 1))


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_ports_and_parameters_are_the_documented_ones(name: str, cfg: GouraudConfig) -> None:
    """Ports table: i0_in I_INT+I_FRAC, di_in I_INT+I_FRAC+1 (two's complement), len_in
    LEN_WIDTH, pixels P*I_INT, mask P (held), last 1 (a strobe with valid) -- the widths the
    benches check the RTL's ports against; parameters I_INT, I_FRAC, P, LEN_WIDTH."""
    spec = units.spec(cfg)
    ops = {p.name: (p.width, p.signed) for p in spec.operands}
    assert ops == {
        "i0": (cfg.i_int + cfg.i_frac, False),
        "di": (cfg.i_int + cfg.i_frac + 1, True),
        "len": (cfg.len_width, False),
    }
    outs = {p.name: (p.width, p.kind) for p in spec.outputs}
    assert outs == {
        "pixels": (cfg.p * cfg.i_int, "data"),
        "mask": (cfg.p, "flag"),
        "last": (1, "strobe"),
    }
    assert unit_parameters(cfg) == {
        "I_INT": cfg.i_int,
        "I_FRAC": cfg.i_frac,
        "P": cfg.p,
        "LEN_WIDTH": cfg.len_width,
    }


# ------------------------------------------------------------------------ the network
@pytest.mark.parametrize("p", [2, 4, 8, 16, 32, 64])
def test_network_rule_prefers_an_addition_then_the_smallest_second_operand(p: int) -> None:
    """Contract: "level 0 are the wired shifts 2^w*dI, w = 0..log2 P; every other multiple 1..P
    gets the lowest level at which it is a sum or difference of two multiples of lower levels, an
    addition preferred, then the smallest second operand": re-derived here by brute force."""
    net = gouraud.increment_network(p)
    assert net.shifts == tuple(1 << w for w in range(p.bit_length()))
    level = dict.fromkeys(net.shifts, 0)
    for adder in net.adders:
        level[adder.target] = adder.level
    for adder in net.adders:
        lower = sorted(m for m, lv in level.items() if lv < adder.level)
        i = adder.target
        additions = [y for y in lower if i - y >= y and (i - y) in lower]
        subtractions = [y for y in lower if i + y in lower]
        assert additions or subtractions, adder
        if additions:
            assert (adder.subtract, adder.a, adder.b) == (False, i - additions[0], additions[0])
        else:
            assert (adder.subtract, adder.a, adder.b) == (
                True,
                i + subtractions[0],
                subtractions[0],
            )
    assert set(level) == set(range(1, p + 1))


# ------------------------------------------------------------------------ conversion
# No per-example deadline: the first example pays numba's compile of the model's kernels
# and a loaded machine slows any example; max_examples bounds the run instead.
@settings(deadline=None)
@given(x=st.integers(-(1 << 40), 1 << 40), f=st.integers(1, 24))
def test_rounding_bias_turns_truncation_into_round_half_up(x: int, f: int) -> None:
    """Contract: "trunc(I0 + bias + i*dI) = round(I0 + i*dI) (fixed.round_shift, tested)": with
    the bias 2^(f-1), dropping f bits (fixed.trunc_shift) is rounding to nearest, ties up, and
    both equal floor(x / 2^f + 1/2) in exact rationals."""
    exact = Fraction(x, 2**f) + Fraction(1, 2)
    expected = exact.numerator // exact.denominator
    assert fixed.trunc_shift(x + (1 << (f - 1)), f) == fixed.round_shift(x, f) == expected


# No per-example deadline: the first example pays numba's compile of the model's kernels
# and a loaded machine slows any example; max_examples bounds the run instead.
@settings(deadline=None)
@given(x=st.integers(-(1 << 40), 1 << 40), hi=st.integers(0, 1 << 16))
def test_saturate_clamps_to_the_output_range(x: int, hi: int) -> None:
    """Contract: "then saturate to 0..2^I_INT - 1": fixed.saturate is min(max(x, lo), hi)."""
    assert fixed.saturate(x, 0, hi) == min(max(x, 0), hi)


# ------------------------------------------------------------------------ lines and segments
def test_mask_comes_from_the_low_bits_of_the_length() -> None:
    """Contract: "mask marks the lanes that belong to it, from the low log2(P) bits of the
    length"; mask is "all ones except in the last segment" (all ones there too when P divides m)."""
    for cfg in (DEFAULT, GouraudConfig(p=2), GouraudConfig(p=16)):
        p = cfg.p
        for length in [*range(1, 4 * p + 2), cfg.len_max]:
            masks = [r["mask"] for r in gouraud.unit_results(7 << cfg.i_frac, 3, length, cfg)]
            low = length & (p - 1)
            assert masks[:-1] == [(1 << p) - 1] * (len(masks) - 1)
            assert masks[-1] == ((1 << low) - 1 if low else (1 << p) - 1), length


def test_every_start_ends_with_exactly_one_last() -> None:
    """Contract: "Every accepted start thus ends with exactly one last" (length 0 included): in
    the model of one line, and in the benches' expectation under the soak's random stimulus
    (resets abort lines: every line that completes has exactly one last, with its final valid)."""
    for length in range(0, 3 * DEFAULT.p + 2):
        lasts = [r["last"] for r in gouraud.unit_results(5 << 12, -(1 << 10), length)]
        assert lasts == [0] * (len(lasts) - 1) + [1]
    for cfg in (DEFAULT, GouraudConfig(p=2, i_frac=4)):
        prediction = soak.predict(cfg, soak.stimulus(cfg, 20_000, seed=77))
        outputs = prediction.outputs
        last_cycles = ones(column(outputs, "last"))
        assert len(last_cycles) == prediction.stats.jobs_completed > 100
        for i in last_cycles:
            assert outputs[i]["valid"] == 1 and outputs[i]["busy"] == 0


def test_python_line_api_refuses_length_0() -> None:
    """Contract: "Length 0 (a 0 written to len; the Python line API raises ValueError for it)"."""
    for call in (gouraud.shade_line, gouraud.segments, gouraud.segment_values):
        with pytest.raises(ValueError, match=r"length = 0 is out of range: legal range is 1\."):
            call(0, 0, 0)


def test_segment_values_are_the_start_register_plus_the_multiples() -> None:
    """Contract: "lanes 1..P-1 add i*dI to the start register, lane 0 is the register itself",
    and the next segment's start I0 + P*dI is written back every clock: lane i of segment s holds
    i0 + bias + (s*P + i)*dI."""
    cfg = DEFAULT
    i0, di, length = 200 << 12, -(37 << 7) - 5, 45
    values = gouraud.segment_values(i0, di, length, cfg)
    start = i0 + cfg.round_bias
    for s in range(values.shape[0]):
        assert values[s, 0] == start
        assert values[s].tolist() == [start + i * di for i in range(cfg.p)]
        start += cfg.p * di


# ------------------------------------------------------------------------ timing (bench model)
@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_bench_expects_the_documented_timing(name: str, cfg: GouraudConfig) -> None:
    """Contract: "busy is high for ceil(m/P) cycles after the edge that accepted start; segment s
    comes out with valid s + 1 cycles after that edge, the last one with last = 1 together with
    busy = 0"; length 0: one empty segment (mask 0, last 1) after one busy cycle."""
    p = cfg.p
    for length in sorted({0, 1, p - 1, p, p + 1, 2 * p + 1, cfg.len_max}):
        d = Drive(cfg)
        d.reset()
        after = d.job(i0=cfg.i0_range[1] // 3, di=-5, len=length)
        nseg = max(1, -(-length // p))
        assert column(after, "busy") == [1] * nseg + [0] * (len(after) - nseg), length
        assert ones(column(after, "valid")) == list(range(1, nseg + 1)), length
        assert ones(column(after, "last")) == [nseg], length
        if length == 0:
            assert after[1]["mask"] == 0


@pytest.mark.parametrize(("name", "cfg"), CONFIGS, ids=IDS)
def test_bench_expects_one_line_every_segments_plus_one(name: str, cfg: GouraudConfig) -> None:
    """Contract: "a new start is already accepted [with the last segment]: one line every
    ceil(m/P) + 1 clocks, back to back"."""
    for length in (1, cfg.p + 1, 3 * cfg.p):
        d = Drive(cfg)
        d.reset()
        d.edge(i0=1 << cfg.i_frac, di=3, len=length)
        first = len(d.outputs)
        period = gouraud.cycles(length, cfg) + 1
        for _ in range(5 * period):
            d.edge(start=1)
        lasts = ones(column(d.outputs[first:], "last"))
        assert lasts == [period * j + period - 1 for j in range(5)], (length, lasts)
        assert d.model.stats.back_to_back == 4


def test_bench_expects_an_empty_line_after_reset_and_held_outputs() -> None:
    """Contract: "after a reset (all registers 0) a start is such an empty line", and between
    segments pixels and mask hold the last segment's values while last is 0."""
    cfg = DEFAULT
    d = Drive(cfg)
    d.reset()
    d.edge(i0=9 << 12, di=1 << 12, len=40)
    d.edge(start=1)
    d.edge()
    out = d.edge(rst_n=0)
    assert (out["busy"], out["valid"], out["mask"], out["last"], out["pixels"]) == (
        0,
        0,
        0,
        0,
        None,
    )
    after = d.job(tail=6)
    assert d.model.last_job.operands == {"i0": 0, "di": 0, "len": 0}
    assert ones(column(after, "valid")) == [1] and ones(column(after, "last")) == [1]
    assert (after[1]["pixels"], after[1]["mask"]) == (0, 0)
    line = d.job(tail=6, i0=17 << 12, di=5 << 10, len=21)
    results = gouraud.unit_results(17 << 12, 5 << 10, 21, cfg)
    for o in line[4:]:  # the cycles after the last segment
        assert (o["pixels"], o["mask"], o["last"]) == (results[-1]["pixels"], 0b00011111, 0)


# ------------------------------------------------------------------------ the soak
def test_soak_stimulus_replays_from_its_seed_and_reaches_the_extremes() -> None:
    """Contract: "The seed is printed in the run's summary; SOAK_SEED=N make sim replays it": the
    stimulus is a function of its seed; it writes the extremes, values across 0 and length 0."""
    cfg = DEFAULT
    stim = soak.stimulus(cfg, 20_000, seed=99)
    assert stim == soak.stimulus(cfg, 20_000, seed=99)
    assert stim != soak.stimulus(cfg, 20_000, seed=100)
    d_lo, d_hi = cfg.di_range
    assert {d_lo, -1, 0, 1, d_hi} <= {s["di_in"] for s in stim if s["di_we"]}
    assert {0, cfg.i0_range[1]} <= {s["i0_in"] for s in stim if s["i0_we"]}
    assert 0 in {s["len_in"] for s in stim if s["len_we"]}
    values = np.array([s["len_in"] for s in stim if s["len_we"]])
    assert values.max() > 4 * cfg.p


# ------------------------------------------------------------------------ RTL parameters, reset
RTL_FILE = Path(__file__).resolve().parent.parent / "rtl" / "gouraud_segment.v"


def rtl_parameters() -> dict[str, str]:
    """The parameters the RTL's module header declares, in order, with their default text."""
    header = RTL_FILE.read_text().split("module gouraud_segment #(", 1)[1].split("\n) (", 1)[0]
    return dict(re.findall(r"^\s*parameter\s+(\w+)\s*=\s*(.+?),?\s*$", header, flags=re.M))


def test_rtl_parameters_are_the_documented_ones() -> None:
    """Parameters: the config fields in UPPER_CASE with the defaults of ``DEFAULT``, and last
    RESET_ALL, default 0 (docs/fpga.md, "Reset"), which no model field maps to."""
    params = rtl_parameters()
    assert list(params) == ["I_INT", "I_FRAC", "P", "LEN_WIDTH", "RESET_ALL"]
    assert params["RESET_ALL"] == "0"
    for field in ("i_int", "i_frac", "p", "len_width"):
        assert params[field.upper()] == str(getattr(DEFAULT, field)), field
    assert set(unit_parameters(DEFAULT)) | {"RESET_ALL"} == set(params)


@pytest.mark.parametrize("reset_all", [0, 1])
def test_bench_expects_the_data_outputs_reset_only_with_reset_all(reset_all: int) -> None:
    """Reset: busy, valid, mask and last are 0 after a reset whatever RESET_ALL; pixels is
    undefined until the next segment with RESET_ALL = 0 (a don't-care: the data path is not
    reset, Icarus shows X) and 0 with RESET_ALL = 1 (every register reset).  The runner builds
    the RTL with the bench's RESET_ALL and tells the monitor (BENCH_RESET_ALL)."""
    d = Drive(DEFAULT)
    d.model.reset_all = bool(reset_all)
    d.reset()
    assert d.outputs[-1]["pixels"] == (0 if reset_all else None)
    d.job(i0=10 << DEFAULT.i_frac, di=1 << DEFAULT.i_frac, len=20)
    out = d.edge(rst_n=0)
    assert (out["busy"], out["valid"], out["mask"], out["last"]) == (0, 0, 0, 0)
    assert out["pixels"] == (0 if reset_all else None)
