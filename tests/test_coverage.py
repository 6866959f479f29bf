# SPDX-License-Identifier: Apache-2.0
"""``make coverage`` (sim/coverage.py): line and toggle coverage under Verilator, every gap
covered or explained by a waiver (sim/coverage_waivers.toml), the figures of
docs/verification.md the script's.

The quick tier runs one unit on one committed vector set (the same code path as the whole
run: the coverage build, the replay, the merge, the annotation, the check) and shows that an
unexplained gap and a stale waiver each fail the run by name; the slow tier runs everything
and compares its table with the one in the docs."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from sim import coverage, coverage_points

pytestmark = pytest.mark.sim

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs" / "verification.md"


def need_verilator() -> None:
    if shutil.which("verilator") is None or shutil.which("verilator_coverage") is None:
        pytest.fail("verilator and verilator_coverage must be on PATH (make tools)")


def test_waivers_file_is_well_formed():
    waivers = coverage_points.load_waivers(coverage.WAIVERS)
    assert waivers
    for w in waivers:
        assert set(w.units) <= set(coverage.UNITS), w
        assert len(w.reason) > 20, f"{w.label()}: say why the gap cannot be closed"


def test_each_unit_s_plan_replays_its_committed_sets_and_its_soaks():
    """Every unit but the core replays each committed vector set of its own and soaks; the BRDF
    unit each of its five forms twice, its committed set brdf_<form> and a soak, both under the
    form's name (one configuration each, merged into one report)."""
    from model.units import brdf
    from sim import coverage_run, units, vector_sets

    for unit in coverage.UNITS:
        if unit == "shading_core":
            continue
        runs = coverage_run.plan(unit)
        sets = {r.name for r in runs if not r.cycles}
        mine = {n for n, (cfg, _) in vector_sets.SETS.items() if units.spec(cfg).toplevel == unit}
        assert sets == mine and sets, unit
        assert any(r.cycles for r in runs), unit
        assert all(units.spec(r.cfg).toplevel == unit for r in runs), unit
    brdf_runs = coverage_run.plan("brdf_unit")
    soaked = {r.config for r in brdf_runs if r.cycles}
    assert {r.config for r in brdf_runs} == soaked == set(brdf.UNIT_CONFIGS)
    assert all(r.cfg == brdf.UNIT_CONFIGS[r.config] for r in brdf_runs)


def point(file: str, kind: str, line: int, what: str, count: int) -> coverage_points.Point:
    return coverage_points.Point(file, kind, line, 0, what, (line,), count)


def test_waivers_match_by_text_region_and_signal_never_by_line_number():
    source = {"u.v": ["module u;", "// check begin", "x = 1;", "`endif", "y = 2;"]}
    region = coverage_points.Waiver(
        ("u",), "u.v", "line", "constant", "r", text="check begin", until="`endif"
    )
    text = coverage_points.Waiver(("u",), "u.v", "line", "constant", "r", text="y = 2")
    bits = coverage_points.Waiver(
        ("u",), "u.v", "toggle", "unreachable bits", "r", signals=("acc*",), bits=((30, 31),)
    )
    assert region.matches("u", point("u.v", "line", 3, "block", 0), source)
    assert not region.matches("u", point("u.v", "line", 5, "block", 0), source)
    assert text.matches("u", point("u.v", "line", 5, "block", 0), source)
    assert not text.matches("other", point("u.v", "line", 5, "block", 0), source)
    assert bits.matches("u", point("u.v", "toggle", 1, "acc_reg[31]", 0), source)
    assert not bits.matches("u", point("u.v", "toggle", 1, "acc_reg[29]", 0), source)
    # a toggle point is covered when the bit rose and fell, a line point when it ran
    assert not point("u.v", "toggle", 1, "a[0]", 1).covered
    assert point("u.v", "toggle", 1, "a[0]", 2).covered
    assert point("u.v", "line", 1, "block", 1).covered


def test_an_unexplained_gap_and_a_stale_waiver_fail_the_run_by_name(tmp_path, capsys):
    """One unit, one committed vector set: without the waiver of bits_next's bit 0 (the 0
    shifted in) that gap is named; a waiver of a signal that does not exist is named stale;
    the run exits 1.  The annotated sources, the merged file and the gaps are written."""
    need_verilator()
    text = coverage.WAIVERS.read_text()
    kept = [b for b in text.split("[[waiver]]") if 'signal = "bits_next"' not in b]
    bogus = (
        '\n[[waiver]]\nunits = ["divider_shift"]\nfile = "divider_shift.v"\nkind = "toggle"\n'
        'signal = "no_such_signal"\ncategory = "constant"\n'
        'reason = "a waiver that explains nothing must be reported as stale"\n'
    )
    waivers = tmp_path / "waivers.toml"
    waivers.write_text("[[waiver]]".join(kept) + bogus)
    out = tmp_path / "cov"
    args = ["--units", "divider_shift", "--runs", "divider_n4", "--out", str(out)]
    assert coverage.main([*args, "--waivers", str(waivers)]) == 1
    said = capsys.readouterr().out
    assert re.search(r"divider_shift: unexplained gap divider_shift\.v:\d+ toggle bits_next", said)
    assert "divider_shift: stale waiver divider_shift.v toggle no_such_signal" in said
    assert (out / "divider_shift" / "coverage.dat").is_file()
    assert (out / "divider_shift" / "annotated" / "divider_shift.v").is_file()
    assert "bits_next" in (out / "divider_shift" / "gaps.md").read_text()
    assert "| `divider_shift` |" in (out / "summary.md").read_text()


def docs_table() -> str:
    return coverage.docs_table(DOCS)


def test_the_docs_name_every_unit_and_every_waiver_category_in_use():
    table = docs_table()
    for unit in coverage.UNITS:
        assert f"| `{unit}` |" in table
    section = DOCS.read_text()[DOCS.read_text().index("## Coverage") :]
    for w in coverage_points.load_waivers(coverage.WAIVERS):
        assert w.category in section, w.category


def test_make_coverage_fails_on_a_docs_table_that_is_not_the_run_s(tmp_path):
    """make coverage (--docs docs/verification.md) compares the whole run's table with the
    page's: equal gives no problem, one changed figure is named.  (The whole run, about 13
    minutes from cold builds, is make coverage's own, outside CI's tiers.)"""
    page = tmp_path / "verification.md"
    page.write_text(DOCS.read_text())
    printed = docs_table()
    assert coverage.docs_problems(printed, page) == []
    first = printed.splitlines()[2]
    changed = printed.replace(first, first.replace("|", "| 1", 2).replace("| 1", "|", 1), 1)
    assert changed != printed
    (problem,) = coverage.docs_problems(changed, page)
    assert "its coverage table is not this run's" in problem and first in problem


def test_the_core_s_gouraud_accumulator_bound_holds_for_every_span():
    """The bound the waiver of gacc_reg's top bits gives (sim/coverage_waivers.toml): with the
    default divider's reciprocals, l * di misses i_end - i_start by -2044 .. +2044 units of
    2^-12 at most, over every length and every difference, less than the 2^11 half level."""
    import numpy as np

    from model.units import divider

    cfg = divider.DEFAULT
    words = divider.read_rom(cfg)
    n = cfg.recip_bits
    top = (1 << 20) - 1
    a = np.arange(-top, top + 1, dtype=np.int64)
    lo, hi = 0, 0
    for length in range(1, 1 << cfg.k_width):
        di = (a * int(words[length]) + (1 << (n - 1))) >> n
        e = length * di - a
        lo, hi = min(lo, int(e.min())), max(hi, int(e.max()))
    assert lo >= -2044 and hi <= 2044 < 1 << 11, (lo, hi)


def test_the_core_s_cubic_coefficients_and_q_stay_in_their_waived_bits():
    """The bounds the waivers of the core's cubic highlight and of the BRDF unit's cubic give
    (sim/coverage_waivers.toml; the same table and widths):
    its coefficient table (the committed image, as the RTL reads it) never sets p0's bit 15,
    b1's bits 17 and 15 or b2's 17 and 16; and over every n's coefficients and every angle-table
    word (and 2^D, cos = 0) the RTL's q = round(tau h, P) + p0 (rtl/brdf_cubic.v, tau floored at
    -16) stays in [1.4e-5, 34.14]: never negative, below 64 (q's bits 30 and up never set), so
    c q < 2^50; r w < 2^38."""
    import numpy as np

    from model.units.brdf import unit

    cfg = unit.UNIT_CONFIGS["cubic"]
    c = cfg.coef_bits
    pairs = np.asarray(unit.read_rom(cfg, "coef"), dtype=np.int64).reshape(-1, 2)
    mask = (1 << c) - 1
    r, p0 = pairs[:, 0] >> c, pairs[:, 0] & mask
    b1, b2 = pairs[:, 1] >> c, pairs[:, 1] & mask
    for name, col, never in (("p0", p0, (15,)), ("b1", b1, (17, 15)), ("b2", b2, (17, 16))):
        assert not int(np.bitwise_or.reduce(col)) & sum(1 << b for b in never), name
    d, p = cfg.cos_data_bits, cfg.work_bits
    w = np.concatenate([np.asarray(unit.read_rom(cfg, "angle"), dtype=np.int64), [1 << d]])

    def rnd(x, s):
        return x << -s if s <= 0 else (x + (1 << (s - 1))) >> s

    lo, hi, cq_max, rw_max = np.inf, -np.inf, 0, 0
    for rn, p0n, b1n, b2n in zip(r, p0, b1, b2, strict=True):
        prw = rn * w
        rw = np.minimum(rnd(prw, c - 11 + d - p), (1 << (p + 6)) - 1)
        t = np.maximum((1 << p) - rw, -(1 << (p + 4)))
        h = rnd(b2n * t, c) + rnd(b1n, c - p)
        q = rnd(t * h, p) + rnd(p0n, c - 1 - p)
        lo, hi = min(lo, int(q.min())), max(hi, int(q.max()))
        cq_max = max(cq_max, int((((1 << d) - w) * np.maximum(q, 0)).max()))
        rw_max = max(rw_max, int(prw.max()))
    assert lo > 0 and hi < 1 << (p + 6), (lo / 2**p, hi / 2**p)
    assert round(lo / 2**p, 6) == 1.4e-5 and round(hi / 2**p, 2) == 34.14
    assert cq_max < 1 << 50 and rw_max < 1 << 38


def test_the_core_s_piecewise_coefficients_num_and_den_stay_in_their_waived_bits():
    """The bounds the waivers of the core's piecewise highlight and of the BRDF unit's piecewise
    form give (sim/coverage_waivers.toml; the same table and widths):
    its coefficient table (the committed image, as the RTL reads it: {r, p0, b1} at port A,
    {b2, s2, beta} at port B) holds the cubic's very words in its first four columns (so the
    cubic's bounds, the test above, hold for its cubic instance), never sets the word's bits 87,
    71, 69, 53 and 52 and always sets bit 35 (s2 in [1, 2)); over every n and every angle-table
    word (and 2^D, cos = 0) the bloom branch (round(r w, P) >= 2^P, rtl/brdf_piecewise.v) has
    w >= 1, so num = c < 2^D; and den = s2r + round(beta rwb, BETA_FRAC) stays below 2^36 for
    every 35-bit rwb (the cubic branch's wrapped ones too)."""
    import numpy as np

    from model.units.brdf import unit

    cfg, cubic = unit.UNIT_CONFIGS["piecewise"], unit.UNIT_CONFIGS["cubic"]
    c, d, p = cfg.coef_bits, cfg.cos_data_bits, cfg.work_bits
    assert cfg.coefficients == ("r", "p0", "b1", "b2", "s2", "beta")
    fracs = {name: q.frac_bits for name, q in cfg.coef_formats.items()}
    assert (fracs["r"], fracs["s2"], fracs["beta"]) == (c - 11, c - 1, c - 1)
    mask = (1 << c) - 1
    ab = np.asarray(unit.read_rom(cfg, "coef"), dtype=np.int64).reshape(-1, 2)
    cols = [(ab[:, j // 3] >> (c * (2 - j % 3))) & mask for j in range(6)]
    pairs = np.asarray(unit.read_rom(cubic, "coef"), dtype=np.int64).reshape(-1, 2)
    cubic_cols = [pairs[:, 0] >> c, pairs[:, 0] & mask, pairs[:, 1] >> c, pairs[:, 1] & mask]
    for name, mine, theirs in zip(cfg.coefficients[:4], cols[:4], cubic_cols, strict=True):
        assert np.array_equal(mine, theirs), name
    words = np.zeros(len(ab), dtype=object)
    for j, col in enumerate(cols):
        words = words + (col.astype(object) << (c * (5 - j)))
    never = int(np.bitwise_or.reduce(words))
    always = int(np.bitwise_and.reduce(words))
    assert [b for b in (87, 71, 69, 53, 52) if never >> b & 1] == []
    assert always >> 35 & 1
    # the image's two port words: A's bit 33 (p0's 15), B's 53 and 52 (b2's 17, 16) never set
    assert not int(np.bitwise_or.reduce(ab[:, 0])) >> 33 & 1
    assert not int(np.bitwise_or.reduce(ab[:, 1])) >> 52 & 3
    assert int(np.bitwise_and.reduce(ab[:, 1])) >> 35 & 1
    r, s2, beta = cols[0], cols[4], cols[5]
    assert int(s2.min()) >= 1 << (c - 1) and int(s2.max()) < 1 << c  # s2 in [1, 2)
    w = np.concatenate([np.asarray(unit.read_rom(cfg, "angle"), dtype=np.int64), [1 << d]])
    shift = fracs["r"] + d - p
    c_bloom = 0
    for rn in r:
        bloom = (rn * w + (1 << (shift - 1))) >> shift >= 1 << p
        c_bloom = max(c_bloom, int(((1 << d) - w[bloom]).max(initial=0)))
    assert 0 < c_bloom < 1 << d
    assert int(r.max()) * (1 << d) < 1 << 38  # r w: bit 38 never set
    s2r_max = int(s2.max()) << (p - fracs["s2"])
    bp_max = (int(beta.max()) * ((1 << (p + 11)) - 1) + (1 << (fracs["beta"] - 1))) >> fracs["beta"]
    assert s2r_max < 1 << 26 and bp_max < 0.6923 * 2**36, bp_max / 2**36
    assert s2r_max + bp_max < 1 << 36  # den: bit 36 never set


def test_the_brdf_cosine_quadratic_and_quadratic_products_stay_in_their_waived_bits():
    """The bounds the waivers of the cosine-quadratic and the quadratic give, in the core's
    highlight and in the BRDF unit (the same widths; the unit registers 7n of any 10-bit n):
    7n w <= 7161 x 2^20 < 2^33; the quadratic's a (its table, the committed image) at most
    786.44 in Q10.8 = 201329, so a w <= 201329 x 2^20 < 2^38 and (a w + 8) >> 4 < 2^34."""
    import numpy as np

    from model.units.brdf import unit

    cq, quad = unit.UNIT_CONFIGS["cosine_quadratic"], unit.UNIT_CONFIGS["quadratic"]
    w_max = 1 << cq.cos_data_bits
    assert cq.cos_data_bits == quad.cos_data_bits == 20
    assert 7 * 1023 == 7161 and 7161 * w_max < 1 << 33
    a = np.asarray(unit.read_rom(quad, "coef"), dtype=np.int64)
    assert int(a.min()) >= 0 and int(a.max()) <= 201329, int(a.max())
    assert 201329 * w_max < 1 << 38 and (201329 * w_max + 8) >> 4 < 1 << 34
