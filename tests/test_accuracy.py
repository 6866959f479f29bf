# SPDX-License-Identifier: Apache-2.0
"""Every accuracy figure is a worst case: ``python -m model accuracy`` (``model.accuracy``).

The figures are checked three ways: the printed value is the computed one rounded *up* (never a
rounded-down miss), the unit pages (docs/<unit>.md) carry exactly what the command prints, and
each search is exhaustive: its worst case is replayed through the bit-exact model, and on a
reduced configuration the search equals a brute force over every input.
"""

from __future__ import annotations

import dataclasses
import math
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from model.study import accuracy
from model.study.accuracy import format_trade
from model.units import divider, gouraud, specular
from model.units.specular import DEFAULT, SpecularConfig

ROOT = Path(__file__).resolve().parent.parent

# The unit pages that carry the figures (docs/<unit>.md, section "Accuracy").
DOCUMENTED_ON = ("divider", "gouraud", "specular")

# What the unit pages state (``python -m model accuracy``), rounded up to the printed digits.
DOCUMENTED = {
    "float_patent": "1.0895 %",
    "float_patent_6": "0.8806 %",
    "float_patent_7": "0.7887 %",
    "float_patent_8": "0.6014 %",
    "float_patent_9": "0.5204 %",
    "float_inflection": "0.2684 %",
    "single_1_taylor": "11.1969 %",
    "single_2_taylor": "4.7040 %",
    "single_2_inflection": "1.0801 %",
    "single_3_taylor": "3.0006 %",
    "single_3_inflection": "0.7108 %",
    "single_16_taylor": "0.5204 %",
    "single_16_inflection": "0.1289 %",
    "float_abs": "4.9682 LSB",
    "float_abs_1000": "2.9040 LSB",
    "rom_rel": "1.1324 %",
    "rom_rel_1": "4.8858 %",
    "tables_add": "0.0827 %",
    "lsb_approx": "0.6184 LSB",
    "lsb_approx_c": "0.6258 LSB",
    "lsb_approx_any_c": "0.9961 LSB",
    "lsb_bound_lo": "0.6283 LSB",
    "lsb_bound_hi": "0.6700 LSB",
    "lsb_exact": "5.4764 LSB",
    "lsb_exact_c": "5.4958 LSB",
    "lsb_exact_any_c": "5.5166 LSB",
    "angle_drift": "0.4942 steps",
    "angle_drift_23": "3.9529 steps",
    "table1_max": "0.44271",
    "table1_max_rel": "1.5625 %",
    "table1_mean": "0.8073 %",
    "divider_drift_20_255": "0.2486 levels",
    "divider_drift_20_256": "0.2496 levels",
    "divider_drift_19_255": "0.4962 levels",
    "divider_drift_11_255": "84.9170 levels",
    "gouraud_drift_12": "0.2498 levels",
    "gouraud_drift_11": "0.4996 levels",
}


@pytest.fixture(scope="module")
def figs() -> accuracy.Figures:
    return accuracy.figures()


# ==================================================================== printed = rounded up
def test_every_figure_is_documented_as_computed(figs) -> None:
    assert [f.key for f in figs.items] == list(DOCUMENTED)
    for f in figs.items:
        assert f.text == DOCUMENTED[f.key], f.key
        printed = Decimal(f.text.split()[0])
        exact = Decimal(f.value) * f.scale
        # The documented bound holds (no rounding down) and is the tightest at its digits.
        assert exact <= printed < exact + Decimal(1).scaleb(-f.digits), f.key


def test_format_up_rounds_toward_plus_infinity() -> None:
    assert accuracy.format_up(0.61830, 4) == "0.6183"
    assert accuracy.format_up(0.618301, 4) == "0.6184"
    assert accuracy.format_up(0.011323159, 4, 100) == "1.1324"
    assert accuracy.format_up(0.0113, 4, 100) == "1.1300"  # the float 0.0113 is just below
    assert accuracy.format_up(0.5, 2) == "0.50"


def unit_rows(table: str, unit: str) -> str:
    """The figures table cut to one unit's rows, under the same header (as its page has it)."""
    header, rule, *rows = table.splitlines()
    return "\n".join([header, rule, *(row for row in rows if row.startswith(f"| {unit} |"))])


def test_docs_carry_what_the_command_prints(figs) -> None:
    """Each unit page (docs/<unit>.md) carries its rows of the figures table and its tables."""
    table = accuracy.format_figures(figs)
    pages = {unit: (ROOT / "docs" / f"{unit}.md").read_text() for unit in DOCUMENTED_ON}
    assert {f.unit for f in figs.items} == set(pages), "every unit's figures have a page"
    for unit, text in pages.items():
        assert unit_rows(table, unit) in text, f"docs/{unit}.md: its rows of the figures table"
        assert "make accuracy" in text and "python -m model accuracy" in text, unit
    spec = pages["specular"]
    assert specular.format_brdf_table() in spec
    assert specular.format_accuracy_table(DEFAULT, figs.specular["default"]) in spec
    assert specular.format_config_table(figs.specular) in spec
    assert format_trade() in pages["divider"]  # the divider's worst error of 255/k, every k


def test_unit_rows_keep_every_row_once(figs) -> None:
    """The pages together carry every row of the table, each on one page only."""
    rows = accuracy.format_figures(figs).splitlines()[2:]
    table = "\n".join(["| header |", "|---|", *rows])
    cut = [r for unit in DOCUMENTED_ON for r in unit_rows(table, unit).splitlines()[2:]]
    assert sorted(cut) == sorted(rows)


# ======================================================== numbers measured independently
def test_independently_measured_numbers(figs) -> None:
    """Figures measured independently of the accuracy command (by hand, in a float check)."""
    acc = figs.specular["default"]
    assert 100 * acc.rom_rel[3 - 1] == pytest.approx(1.1323, abs=5e-5)  # broke the old 0.0113
    assert acc.rom_rel[3 - 1] > 0.0113
    assert 100 * acc.rom_rel[0] == pytest.approx(4.886, abs=5e-4)
    assert 100 * (acc.rom_rel - acc.float_rel)[1:].max() == pytest.approx(0.083, abs=5e-4)
    assert 100 * specular.float_errors(DEFAULT)[8 - 1] == pytest.approx(0.6014, abs=5e-5)
    # The unit's own error: one pixel at n = 13 gives 143 against the float 142.3817.
    out = specular.shade_line(255 << 8, 0, 12714694, 13, 0)
    zeta = 12714694 / 2**26 * math.pi / 2
    ref = 255 * math.cos(specular.alpha_value(13, 16) * zeta) ** 16
    assert list(out) == [143] and ref == pytest.approx(142.3817, abs=5e-5)
    assert figs["lsb_approx"].value == pytest.approx(143 - ref, abs=1e-12)
    # About 1 LSB at the largest C, through saturation.
    assert figs["lsb_approx_any_c"].value > 0.99


def test_up5k_numbers(figs) -> None:
    """UP5K: ROM 12 as 4 x 2^11 x 12 bits, so that ROM 9 (1024 x 17: five 1024 x 4
    RAM40 blocks) and ROM 12 (per table six 2048 x 2 blocks) take 29 of the UP5K's 30 RAM40; its
    figures as docs/specular.md gives them (its per-n table, and its row of the config table)."""
    cfg = specular.UP5K
    assert specular.ROM_CONFIGS["up5k"] is cfg
    assert (cfg.rom_addr_bits, cfg.rom_data_bits, cfg.ks) == (11, 12, (1, 2, 4, 16))
    rom9 = math.ceil(cfg.a_width / 4)  # 1024 x 4 per RAM40
    rom12 = cfg.num_tables * math.ceil(cfg.rom_data_bits / 2)  # 2048 x 2 per RAM40
    assert (rom9, rom12) == (5, 24) and rom9 + rom12 <= 30
    acc = figs.specular["up5k"]
    assert 100 * acc.rom_rel[3 - 1] == pytest.approx(1.18849, abs=5e-5)
    assert acc.out_lsb_exact.max() == pytest.approx(5.50790, abs=5e-5)
    assert acc.out_lsb_approx.max() == pytest.approx(0.75204, abs=5e-5)
    assert acc.approx_c_full.value == pytest.approx(0.77367, abs=5e-5)
    assert acc.exact_c_full.value == pytest.approx(5.54158, abs=5e-5)
    assert acc.exact_any_c.value == pytest.approx(5.56700, abs=5e-5)
    # Against the default: the 12-bit words and the halved tables cost at most 0.14 LSB
    default = figs.specular["default"]
    assert acc.out_lsb_approx.max() - default.out_lsb_approx.max() < 0.14
    text = (ROOT / "docs" / "specular.md").read_text()
    assert specular.format_accuracy_table(cfg, acc) in text


# ==================================================================== worst cases replayed
def replay(w: specular.Worst, cfg: SpecularConfig, exact: bool) -> float:
    """|shade_line(c, 0, z, n, 0) - C f| through the public bit-exact call."""
    out = int(specular.shade_line(w.c, 0, w.z, w.n, 0, cfg)[0])
    k = specular.decode_k(w.n, cfg)
    zeta = w.z / 2.0**cfg.z_frac_bits * (math.pi / 2)
    if exact:
        f = max(math.cos(zeta), 0.0) ** w.n
    else:
        f = math.cos(min(specular.alpha_value(w.n, k, cfg.alpha) * zeta, math.pi / 2)) ** k
    return abs(out - w.c / 2.0**cfg.c_frac_bits * f)


@pytest.mark.parametrize("name", list(specular.ROM_CONFIGS))
def test_worst_cases_replay_through_shade_line(figs, name: str) -> None:
    cfg = specular.ROM_CONFIGS[name]
    acc = figs.specular[name]
    for w, exact in (
        (acc.approx_c_full, False),
        (acc.approx_any_c, False),
        (acc.exact_c_full, True),
        (acc.exact_any_c, True),
    ):
        assert replay(w, cfg, exact) == pytest.approx(w.value, abs=1e-9), w
    c_full = cfg.out_max << cfg.c_frac_bits
    assert acc.approx_c_full.c <= c_full and acc.exact_c_full.c <= c_full
    for n in (1, 3, 13, 1000, int(np.argmax(acc.out_lsb_approx)) + 1):
        for arr, zs, exact in (
            (acc.out_lsb_approx, acc.out_approx_z, False),
            (acc.out_lsb_exact, acc.out_exact_z, True),
        ):
            w = specular.Worst(float(arr[n - 1]), n, c_full, int(zs[n - 1]))
            assert replay(w, cfg, exact) == pytest.approx(w.value, abs=1e-9), (n, exact)


def test_angle_drift_bound_is_reached() -> None:
    for cfg in (DEFAULT, SpecularConfig(z_frac_bits=23)):
        assert specular.angle_drift_example(cfg) == specular.angle_drift_steps(cfg)


# ==================================================================== exhaustive = brute force
SMALL = SpecularConfig(
    c_int_bits=4,
    c_frac_bits=2,
    z_frac_bits=9,
    len_width=4,
    a_frac_bits=8,
    rom_addr_bits=6,
    rom_data_bits=8,
    out_width=4,
)
"""Small enough to try every n, every angle register value up to 3pi/2 and every C."""


def brute_force(cfg: SpecularConfig) -> dict[str, np.ndarray | float]:
    t = specular.tables(cfg)
    z_cap = 3 << cfg.z_frac_bits
    z = np.arange(z_cap + 1, dtype=np.int64)
    zeta = z / 2.0**cfg.z_frac_bits * (np.pi / 2)
    c = np.arange(cfg.c_format.hi + 1)
    c_full = cfg.out_max << cfg.c_frac_bits
    shift = cfg.c_frac_bits + cfg.rom_data_bits
    res = {key: np.zeros(1000) for key in ("rom_rel", "approx", "exact")}
    res.update({key: 0.0 for key in ("approx_c", "approx_any", "exact_c", "exact_any")})
    for n in range(1, 1001):
        k = specular.decode_k(n, cfg)
        a_word, tsel = int(t.rom9[n]), int(t.tsel[n])
        words = np.empty(z.size, dtype=np.int64)
        specular.rom12_path_kernel(z, a_word, tsel, *t.pixel_args[:4], words)
        assert words[-1] == 0  # past 3pi/2 nothing lights (the word is non-increasing)
        out = np.minimum((c[:, None] * words + (1 << (shift - 1))) >> shift, cfg.out_max)
        approx = np.cos(np.minimum(specular.alpha_value(n, k, cfg.alpha) * zeta, np.pi / 2)) ** k
        assert approx[-1] < 1e-15  # and the approximation is 0 there too
        exact = np.maximum(np.cos(zeta), 0.0) ** n
        for key, f in (("approx", approx), ("exact", exact)):
            err = np.abs(out - (c / 2.0**cfg.c_frac_bits)[:, None] * f)
            res[key][n - 1] = err[c_full].max()
            res[f"{key}_c"] = max(res[f"{key}_c"], err[: c_full + 1].max())
            res[f"{key}_any"] = max(res[f"{key}_any"], err.max())
        d_e = np.pi / 2 if n == 1 else np.arctan(1 / np.sqrt(n - 1))
        keep = (zeta <= d_e) & (exact >= specular.REL_FLOOR)
        res["rom_rel"][n - 1] = np.max(
            np.abs(words[keep] / 2.0**cfg.rom_data_bits / exact[keep] - 1)
        )
    return res


def test_exhaustive_search_equals_brute_force_on_a_small_unit() -> None:
    acc = specular.fixed_point_accuracy(SMALL)
    ref = brute_force(SMALL)
    np.testing.assert_allclose(acc.rom_rel, ref["rom_rel"], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(acc.out_lsb_approx, ref["approx"], rtol=1e-12)
    np.testing.assert_allclose(acc.out_lsb_exact, ref["exact"], rtol=1e-12)
    assert acc.approx_c_full.value == pytest.approx(ref["approx_c"], rel=1e-12)
    assert acc.approx_any_c.value == pytest.approx(ref["approx_any"], rel=1e-12)
    assert acc.exact_c_full.value == pytest.approx(ref["exact_c"], rel=1e-12)
    assert acc.exact_any_c.value == pytest.approx(ref["exact_any"], rel=1e-12)
    # The brute force above reads the words through the model's kernel: the public call agrees.
    rng = np.random.default_rng(11)
    t = specular.tables(SMALL)
    picks = zip(
        rng.integers(1, 1001, 50), rng.integers(0, 64, 50), rng.integers(0, 1537, 50), strict=True
    )
    for n, c, z in picks:
        words = np.empty(1, dtype=np.int64)
        specular.rom12_path_kernel(
            np.array([z]), int(t.rom9[n]), int(t.tsel[n]), *t.pixel_args[:4], words
        )
        expect = min((int(c) * int(words[0]) + (1 << 9)) >> 10, SMALL.out_max)
        assert specular.shade_line(int(c), 0, int(z), int(n), 0, SMALL)[0] == expect


@pytest.mark.parametrize("name", ["small", *specular.ROM_CONFIGS, *specular.KEPT_CONFIGS])
def test_the_epicentre_walk_gives_the_whole_walk_s_rom_error(name: str) -> None:
    """``rom_rel_errors`` (the walk stopped at the epicentre's end, what the BRDF budget search
    runs) gives ``fixed_point_accuracy``'s rom_rel and rom_rel_z exactly, and the brute force's
    on the small unit."""
    cfg = SMALL if name == "small" else {**specular.ROM_CONFIGS, **specular.KEPT_CONFIGS}[name]
    rel, rel_z = specular.rom_rel_errors(cfg)
    acc = specular.fixed_point_accuracy(cfg)
    assert np.array_equal(rel, acc.rom_rel) and np.array_equal(rel_z, acc.rom_rel_z)
    if name == "small":
        np.testing.assert_allclose(rel, brute_force(SMALL)["rom_rel"], rtol=1e-12, atol=1e-15)


def test_float_maxima_are_not_below_any_sample() -> None:
    """The exact float maxima against dense sampling: never below a sample, and the samples
    come as close as their spacing allows (the maximum is found, not overestimated)."""
    for n, k, alpha in [(3, 4, "taylor"), (8, 16, "taylor"), (1000, 16, "taylor"),
                        (3, 4, "inflection"), (1000, 2, "inflection"), (500, 3, "inflection"),
                        (2, 1, "taylor"), (40, 16, "inflection")]:  # fmt: skip
        d = np.linspace(0.0, specular.epicentre(n), 200001)
        rel = np.abs(specular.brdf_approx(d, n, k, alpha) / np.cos(d) ** n - 1)
        exact = specular.brdf_max_rel_error(n, k, alpha)
        assert rel.max() <= exact + 1e-12 and exact - rel.max() < 1e-9, (n, k, alpha)
        d = np.linspace(0.0, np.pi, 400001)
        err = np.abs(specular.brdf_approx(d, n, k, alpha) - np.maximum(np.cos(d), 0.0) ** n)
        bound = specular.brdf_max_abs_error(n, k, alpha)
        a = specular.alpha_value(n, k, alpha)
        slope = a * specular.cos_power_max_slope(k) + specular.cos_power_max_slope(n)
        # The samples can miss a corner (a d = pi/2 for k = 1) by a slope times half a step.
        assert err.max() <= bound < err.max() + slope * (d[1] - d[0]) / 2, (n, k, alpha)


def test_taylor_error_grows_to_the_epicentre_edge() -> None:
    """The reason the patent mapping's maximum is the end point: monotone in d."""
    for n in (3, 6, 7, 8, 100, 1000):
        k = specular.decode_k(n)
        d = np.linspace(0.0, specular.epicentre(n), 20001)
        rel = np.abs(specular.brdf_approx(d, n, k) / np.cos(d) ** n - 1)
        assert (np.diff(rel) >= -1e-13).all(), n  # float noise at d ~ 0


def test_cos_power_max_slope_is_the_largest_slope() -> None:
    x = np.linspace(0, math.pi / 2, 200001)
    for k in (1, 2, 4, 16):
        dense = float(np.max(k * np.cos(x) ** (k - 1) * np.sin(x)))
        assert dense <= specular.cos_power_max_slope(k) < dense + 1e-9


def test_divider_line_drift_is_exhaustive() -> None:
    """For the article's unit every (dividend, divisor) is tried: the worst is at the largest
    dividend magnitude, as ``line_drift`` assumes."""
    cfg = divider.ARTICLE
    lo, hi = cfg.a_range
    worst = Fraction(0)
    for k in range(1, cfg.k_max + 1):
        r = divider.reciprocal(k, cfg.recip_bits)
        for a in (lo, lo + 1, -1, 1, hi):
            worst = max(worst, abs(Fraction(a * k * r, 2**cfg.recip_bits) - a))
    a = np.arange(lo, hi + 1)
    ks = np.arange(1, cfg.k_max + 1)
    r = divider.reciprocal(ks, cfg.recip_bits)
    every = np.abs(a[:, None] * (ks * r - 2**cfg.recip_bits)[None, :]) / 2**cfg.recip_bits
    assert every.max() == float(worst)
    assert divider.line_drift(cfg.recip_bits, cfg.k_max, -lo)[0] == every.max()


@pytest.mark.parametrize(("i_frac", "len_width"), [(4, 6), (3, 5)])
def test_gouraud_drift_is_exact_on_small_units(i_frac: int, len_width: int) -> None:
    """Every line length and every end difference: the rounded increment's drift."""
    cfg = gouraud.GouraudConfig(i_frac=i_frac, len_width=len_width, i_int=4, p=2)
    d = np.arange(-(1 << (cfg.i_int + i_frac)), 1 << (cfg.i_int + i_frac))
    worst = 0
    for m in range(2, cfg.len_max + 1):
        q = np.floor(d / (m - 1) + 0.5).astype(np.int64)  # rounded to nearest, ties up
        worst = max(worst, int(np.abs((m - 1) * q - d).max()))
    assert worst / 2.0**i_frac == gouraud.drift_worst(cfg)


def test_gouraud_drift_at_the_default_longest_line() -> None:
    cfg = gouraud.DEFAULT
    d = np.arange(-(1 << 20), 1 << 20)
    m = cfg.len_max
    q = (2 * d + (m - 1)) // (2 * (m - 1))  # floor(d / (m-1) + 1/2), exact integers
    assert np.abs((m - 1) * q - d).max() / 2.0**cfg.i_frac == gouraud.drift_worst(cfg)
    assert gouraud.drift_worst(cfg) == gouraud.drift_bound(cfg)  # 2046 is even


def test_a_kept_range_unit_is_measured_on_its_kept_n_only() -> None:
    """A unit keeping n = 17..40 (``specular.KEPT``) refuses every other n: its exhaustive
    figures are those of the same unit keeping every n, on 17..40, and 0 elsewhere."""
    kept, full = specular.KEPT, dataclasses.replace(specular.KEPT, n_first=1, n_last=1000)
    a, b = specular.fixed_point_accuracy(kept), specular.fixed_point_accuracy(full)
    inside = slice(kept.n_first - 1, kept.n_last)
    for name in ("rom_rel", "out_lsb_exact", "out_lsb_approx"):
        mine, theirs = getattr(a, name), getattr(b, name)
        np.testing.assert_array_equal(mine[inside], theirs[inside], err_msg=name)
        assert not mine[: kept.n_first - 1].any() and not mine[kept.n_last :].any(), name
        assert mine[inside].max() > 0, name
    np.testing.assert_array_equal(a.float_rel, b.float_rel)
