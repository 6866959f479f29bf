# SPDX-License-Identifier: Apache-2.0
"""The segment Gouraud unit model: the article's table, the derived network, exactness against
per-pixel accumulation, conversion and saturation, widths, timing, bad input."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from model.units import divider, fixed, gouraud
from model.units.gouraud import DEFAULT, GouraudConfig

README = Path(__file__).resolve().parent.parent / "docs" / "gouraud.md"

# The article's table (docs/gouraud.md): segment size p -> increments one add/sub reaches.
ARTICLE_INCREMENTS = {2: 2, 4: 4, 8: 8, 16: 14, 32: 22, 64: 32}


def accumulate(i0: int, di: int, n: int) -> list[int]:
    """Plain per-pixel accumulation I(x+1) = I(x) + dI, exact Python integers."""
    out, value = [], i0
    for _ in range(n):
        out.append(value)
        value += di
    return out


def convert(value: int, cfg: GouraudConfig) -> int:
    """Round half up to an integer level and clamp, via exact rationals (not fixed.py)."""
    level = Fraction(value, 2**cfg.i_frac) + Fraction(1, 2)
    return min(max(level.numerator // level.denominator, 0), cfg.out_max)


configs = st.builds(
    lambda p, i_int, i_frac, extra: GouraudConfig(
        i_int=i_int, i_frac=i_frac, p=p, len_width=min(16, p.bit_length() + extra)
    ),
    st.sampled_from(gouraud.LANE_COUNTS),
    st.integers(1, 16),
    st.integers(1, 24),
    st.integers(0, 8),
)


@st.composite
def lines(draw, cfg_strategy=configs):
    cfg = draw(cfg_strategy)
    i0 = draw(st.integers(*cfg.i0_range))
    di = draw(st.integers(*cfg.di_range) | st.integers(-(1 << cfg.i_frac), 1 << cfg.i_frac))
    length = draw(st.integers(1, cfg.len_max))
    return cfg, i0, di, length


# ------------------------------------------------------------------------ the article's table
@pytest.mark.parametrize("p", sorted(ARTICLE_INCREMENTS))
def test_increment_count_reproduces_the_article(p: int) -> None:
    assert gouraud.increment_count(p) == ARTICLE_INCREMENTS[p]


@pytest.mark.parametrize("p", sorted(ARTICLE_INCREMENTS))
def test_network_level_one_is_what_one_adder_reaches(p: int) -> None:
    """The derived network's shifts and level-1 adders make exactly increment_count(p) of the
    increments 0..p-1 (0 needs nothing): the two derivations agree."""
    net = gouraud.increment_network(p)
    one_adder = {0, *net.shifts} | {a.target for a in net.adders if a.level == 1}
    assert sum(1 for i in range(p) if i in one_adder) == gouraud.increment_count(p)


def test_network_for_8_is_the_articles_four_adders() -> None:
    net = gouraud.increment_network(8)
    assert net.shifts == (1, 2, 4, 8)
    assert [a.describe() for a in net.adders] == [
        "3dI = 2dI + 1dI",
        "5dI = 4dI + 1dI",
        "6dI = 4dI + 2dI",
        "7dI = 8dI - 1dI",
    ]
    assert net.adder_count == 4 and net.levels == 1


def test_network_small_and_sixteen() -> None:
    assert gouraud.increment_network(2).adders == () and gouraud.increment_network(2).levels == 0
    assert [a.describe() for a in gouraud.increment_network(4).adders] == ["3dI = 2dI + 1dI"]
    net16 = gouraud.increment_network(16)
    second = [a.describe() for a in net16.adders if a.level == 2]
    assert second == ["11dI = 10dI + 1dI", "13dI = 12dI + 1dI"]
    assert net16.levels == 2 and net16.per_level() == [9, 2]


@pytest.mark.parametrize("p", sorted(ARTICLE_INCREMENTS))
def test_network_makes_every_multiple_from_lower_levels(p: int) -> None:
    net = gouraud.increment_network(p)
    level = dict.fromkeys(net.shifts, 0)
    value = {s: s for s in net.shifts}  # dI = 1: each multiple must come out as itself
    for adder in net.adders:
        assert level[adder.a] < adder.level and level[adder.b] < adder.level, adder
        assert max(level[adder.a], level[adder.b]) == adder.level - 1, adder  # not too late
        value[adder.target] = value[adder.a] + (
            -value[adder.b] if adder.subtract else value[adder.b]
        )
        level[adder.target] = adder.level
    assert value == {i: i for i in range(1, p + 1)}
    # Minimal: a level-L multiple is no sum or difference of two multiples of lower levels.
    for adder in net.adders:
        lower = [m for m, lv in level.items() if lv < adder.level - 1]
        sums = {x + y for x in lower for y in lower} | {x - y for x in lower for y in lower}
        assert adder.target not in sums, adder


def test_readme_network_table_is_generated_from_the_model() -> None:
    assert gouraud.format_network_table() in README.read_text()


def test_adder_counts() -> None:
    assert gouraud.adder_counts(8) == {
        "network": 4,
        "network_levels": 1,
        "segment": 8,
        "bias": 1,
        "total": 13,
    }
    for p in gouraud.LANE_COUNTS:
        c = gouraud.adder_counts(p)
        assert c["total"] == c["network"] + p + 1


# ------------------------------------------------------------------------ exactness
# No per-example deadline: the first example pays numba's compile of the model's kernels
# and a loaded machine slows any example; max_examples bounds the run instead.
@settings(max_examples=300, deadline=None)
@given(lines())
def test_segments_equal_per_pixel_accumulation(line) -> None:
    """The parallel computation (network multiples, lane adders, carried start) is plain
    accumulation I(x+1) = I(x) + dI, exactly, over every lane of every segment."""
    cfg, i0, di, length = line
    values = gouraud.segment_values(i0, di, length, cfg)
    nseg = -(-length // cfg.p)
    assert values.shape == (nseg, cfg.p)
    expected = accumulate(i0 + cfg.round_bias, di, nseg * cfg.p)
    assert values.ravel().tolist() == expected


# No per-example deadline: the first example pays numba's compile of the model's kernels
# and a loaded machine slows any example; max_examples bounds the run instead.
@settings(max_examples=300, deadline=None)
@given(lines())
def test_shade_line_is_rounded_and_saturated_exact_values(line) -> None:
    cfg, i0, di, length = line
    pixels = gouraud.shade_line(i0, di, length, cfg)
    exact = accumulate(i0, di, length)
    assert pixels.tolist() == [convert(v, cfg) for v in exact]
    # The named steps of fixed.py give the same: round_shift then saturate.
    assert pixels.tolist() == [
        fixed.saturate(fixed.round_shift(v, cfg.i_frac), 0, cfg.out_max) for v in exact
    ]


# No per-example deadline: the first example pays numba's compile of the model's kernels
# and a loaded machine slows any example; max_examples bounds the run instead.
@settings(max_examples=200, deadline=None)
@given(lines())
def test_never_wraps_monotone(line) -> None:
    """Saturation, not wrap-around: a line with dI >= 0 never goes down, dI <= 0 never up."""
    cfg, i0, di, length = line
    steps = np.diff(gouraud.shade_line(i0, di, length, cfg))
    assert (steps >= 0).all() if di >= 0 else (steps <= 0).all()


def test_segments_mask_and_shapes() -> None:
    cfg = DEFAULT
    for length in (1, 7, 8, 9, 16, 17, cfg.len_max):
        seg = gouraud.segments(100 << 12, -(3 << 11), length, cfg)
        nseg = -(-length // 8)
        assert seg.pixels.shape == seg.mask.shape == (nseg, 8)
        assert seg.mask.sum() == length
        assert seg.mask[:-1].all()
        assert seg.mask[-1].tolist() == [j < length - 8 * (nseg - 1) for j in range(8)]
        assert len(gouraud.shade_line(100 << 12, -(3 << 11), length, cfg)) == length


def test_rounding_ties_go_up_and_the_top_saturates() -> None:
    cfg = DEFAULT
    half = 1 << 11
    # 0.5 -> 1, 1.5 -> 2, 2.5 -> 3: ties up
    assert gouraud.shade_line(half, 1 << 12, 3, cfg).tolist() == [1, 2, 3]
    # The largest I0 (255 + 4095/4096) rounds to 256: saturated to 255, not wrapped to 0
    i_hi = cfg.i0_range[1]
    assert gouraud.shade_line(i_hi, 0, 2, cfg).tolist() == [255, 255]
    d_lo, d_hi = cfg.di_range
    assert gouraud.shade_line(i_hi, d_hi, 20, cfg).tolist() == [255] * 20
    assert gouraud.shade_line(0, d_lo, 20, cfg).tolist() == [0] * 20
    assert gouraud.shade_line(0, d_hi, 3, cfg).tolist() == [0, 255, 255]


def divider_increment(i_a: int, i_b: int, length: int) -> int:
    """The host's increment (I_b - I_a) / (length - 1) from the shift-add divider, Q.12."""
    q = divider.divide(i_b - i_a, length - 1, divider.DEFAULT)
    return fixed.round_shift(q, divider.DEFAULT.recip_bits)


@pytest.mark.parametrize("upward", [True, False])
def test_divider_overshoot_saturates_instead_of_wrapping(upward: bool) -> None:
    """Approximate increments from the shift-add divider overshoot the end value on some
    lines: past the top of Q8.12 (or below 0), where a wrapping unit would jump 255 <-> 0."""
    cfg = DEFAULT
    i_hi = cfg.i0_range[1]
    i_a, i_b = (0, i_hi) if upward else (i_hi, 0)
    overshooting = []
    for length in range(2, cfg.len_max + 1):
        di = divider_increment(i_a, i_b, length)
        end = i_a + (length - 1) * di
        if (end > i_hi) if upward else (end < 0):
            overshooting.append((length, di))
    assert len(overshooting) > 10
    for length, di in overshooting[:: max(1, len(overshooting) // 20)]:
        pixels = gouraud.shade_line(i_a, di, length, cfg)
        assert pixels[-1] == (255 if upward else 0), (length, di)
        assert pixels.tolist() == sorted(pixels.tolist(), reverse=not upward)


def test_drift_bound_is_the_reason_for_12_fraction_bits() -> None:
    assert gouraud.drift_bound(DEFAULT) <= 0.25
    assert gouraud.drift_bound(GouraudConfig(i_frac=11)) > 0.49
    # Measured: exact end values I_b over the longest line, increment rounded to 2**-12.
    cfg = DEFAULT
    m = cfg.len_max
    worst = Fraction(0)
    for i_b in range(0, cfg.i0_range[1] + 1, 997):
        exact = Fraction(i_b, m - 1)
        di = (exact + Fraction(1, 2)).__floor__()
        worst = max(worst, abs((m - 1) * di - i_b) / Fraction(2**cfg.i_frac))
    assert worst <= gouraud.drift_bound(cfg)


def test_default_formats_match_the_divider() -> None:
    assert DEFAULT.di_width == divider.DEFAULT.a_width  # difference of two Q8.12 intensities
    assert DEFAULT.len_width == divider.DEFAULT.k_width
    assert DEFAULT.i0_format.describe() == "unsigned Q8.12"
    assert DEFAULT.di_format.describe() == "signed Q9.12"
    assert DEFAULT.di_range == (-(256 << 12), (256 << 12) - 1)


# ------------------------------------------------------------------------ widths
def minimal_width(cfg: GouraudConfig) -> int:
    """The smallest signed width holding every value the start register and lanes take."""
    w_i, m, bias = cfg.i_width, 1 << cfg.len_width, cfg.round_bias
    lo = bias - m * (1 << w_i)
    hi = (1 << w_i) - 1 + bias + m * ((1 << w_i) - 1)
    width = 1
    while not (-(1 << (width - 1)) <= lo and hi <= (1 << (width - 1)) - 1):
        width += 1
    return width


# No per-example deadline: the first example pays numba's compile of the model's kernels
# and a loaded machine slows any example; max_examples bounds the run instead.
@settings(max_examples=300, deadline=None)
@given(configs)
def test_acc_width_is_minimal(cfg: GouraudConfig) -> None:
    assert cfg.acc_width == minimal_width(cfg)
    assert cfg.inc_width == cfg.di_width + cfg.log2_p


@pytest.mark.parametrize(
    "cfg",
    [DEFAULT, GouraudConfig(p=2, i_frac=4), GouraudConfig(i_int=2, i_frac=2, p=4, len_width=10)],
)
def test_extreme_lines_reach_both_ends_of_acc_width(cfg: GouraudConfig) -> None:
    """The longest line with the extreme operands: the next start after its last segment is
    exactly the bound acc_width is sized for (so no legal input wraps, and the width is tight)."""
    i_lo, i_hi = cfg.i0_range
    d_lo, d_hi = cfg.di_range
    n, p = cfg.len_max, cfg.p
    lo_w, hi_w = fixed.signed_range(cfg.acc_width)
    down = gouraud.segment_values(i_lo, d_lo, n, cfg)
    up = gouraud.segment_values(i_hi, d_hi, n, cfg)
    last_start_down = int(down[-1, 0]) + p * d_lo  # what the start register takes last
    last_start_up = int(up[-1, 0]) + p * d_hi
    assert last_start_down == cfg.round_bias - (1 << cfg.len_width) * (1 << cfg.i_width)
    assert lo_w <= last_start_down and last_start_up <= hi_w
    assert lo_w <= down.min() and up.max() <= hi_w
    narrower = fixed.signed_range(cfg.acc_width - 1)
    assert last_start_down < narrower[0] or last_start_up > narrower[1]


# ------------------------------------------------------------------------ timing and RTL view
def test_cycles_and_valid_offsets() -> None:
    for cfg in (DEFAULT, GouraudConfig(p=2), GouraudConfig(p=16)):
        p = cfg.p
        for length in (1, p - 1, p, p + 1, 2 * p, cfg.len_max):
            nseg = (length + p - 1) // p
            assert gouraud.cycles(length, cfg) == nseg
            assert gouraud.valid_offsets(length, cfg) == list(range(1, nseg + 1))
        assert gouraud.cycles(0, cfg) == 1 and gouraud.valid_offsets(0, cfg) == [1]
    assert gouraud.cycles(2047) == 256


def test_unit_results_pack_the_segments() -> None:
    cfg = DEFAULT
    i0, di, length = 17 << 12, 5 << 10, 21
    seg = gouraud.segments(i0, di, length, cfg)
    res = gouraud.unit_results(i0, di, length, cfg)
    assert len(res) == 3 and [r["last"] for r in res] == [0, 0, 1]
    assert [r["mask"] for r in res] == [0xFF, 0xFF, 0b00011111]
    for s, r in enumerate(res):
        lanes = [(r["pixels"] >> (8 * j)) & 0xFF for j in range(8)]
        assert lanes == seg.pixels[s].tolist()  # lane 0 in the low bits
    assert res[0]["pixels"] & 0xFF == 17 and (res[0]["pixels"] >> 8) & 0xFF == 18  # 17 + 1.25


def test_length_zero_in_the_rtl_view_is_one_empty_segment() -> None:
    cfg = DEFAULT
    res = gouraud.unit_results(3 << 12, 1 << 12, 0, cfg)
    assert len(res) == 1 and res[0]["mask"] == 0 and res[0]["last"] == 1
    assert res[0]["pixels"] == gouraud.pack_pixels([3, 4, 5, 6, 7, 8, 9, 10], cfg)
    assert gouraud.unit_results(0, 0, 0, cfg) == [{"pixels": 0, "mask": 0, "last": 1}]


# ------------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    ("call", "match"),
    [
        (
            lambda: gouraud.segments(0, 0, 0),
            r"length = 0 is out of range: legal range is 1\.\.2047",
        ),
        (lambda: gouraud.shade_line(0, 0, 2048), r"length = 2048 is out of range"),
        (
            lambda: gouraud.shade_line(-1, 0, 5),
            r"i0 = -1 is out of range: legal range is 0\.\.1048575",
        ),
        (lambda: gouraud.shade_line(1 << 20, 0, 5), r"i0 = 1048576 is out of range"),
        (
            lambda: gouraud.shade_line(0, 1 << 20, 5),
            r"di = 1048576 is out of range: legal range is -1048576\.\.1048575",
        ),
        (lambda: gouraud.shade_line(0, -(1 << 20) - 1, 5), r"di = -1048577 is out of range"),
        (lambda: gouraud.shade_line(0.5, 0, 5), r"i0 must be an integer"),
        (lambda: gouraud.segment_values(0, 0, -1), r"length = -1 is out of range"),
        (lambda: gouraud.shade_line(0, [1, 2], 5), r"di must be a single integer"),
        (
            lambda: gouraud.unit_results(0, 0, 2048),
            r"length = 2048 is out of range: legal range is 0",
        ),
        (lambda: gouraud.cycles(-1), r"length = -1 is out of range: legal range is 0\.\.2047"),
        (lambda: GouraudConfig(p=3), r"p = 3 is out of range: legal values are 2, 4, 8, 16"),
        (lambda: GouraudConfig(p=32), r"p = 32 is out of range"),
        (lambda: GouraudConfig(i_frac=0), r"i_frac = 0 is out of range"),
        (lambda: GouraudConfig(i_int=17), r"i_int = 17 is out of range"),
        (
            lambda: GouraudConfig(p=8, len_width=3),
            r"len_width = 3 is out of range: legal widths are 4",
        ),
        (lambda: gouraud.increment_count(12), r"p = 12 is out of range"),
        (lambda: gouraud.increment_count(128), r"p = 128 is out of range"),
        (lambda: gouraud.increment_network(1), r"p = 1 is out of range"),
    ],
)
def test_bad_input_names_operand_value_and_range(call, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        call()
