# SPDX-License-Identifier: Apache-2.0
"""The BRDF family's fixed-point units (model.units.brdf.fixed, fixed_accuracy, budget): the
walk over both ends of every angle-table address equals a brute force over every angle code,
the forms it relies on fall with the angle, random angles stay within the worst errors found,
the tables docs/brdf.md shows are what the code computes, bad widths are refused by name, the
table bits add up and the budget winner fits the patent's budget."""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from model.units import brdf
from model.units.brdf import budget
from model.units.specular import (
    DEFAULT,
    N_MAX,
    NARROW,
    REL_FLOOR,
    SpecularConfig,
    fixed_point_accuracy,
    float_errors,
)

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs/brdf.md"
SOME_N = (1, 2, 3, 5, 8, 27, 100, 640, 1000)


def _brute_force(cfg: brdf.FixedConfig, n: int) -> tuple[float, float, float]:
    """(abs LSB, relative vs own float, relative vs cos^n) over every angle code of n's
    epicentre, both signs, computed directly."""
    zf, o = cfg.angle.z_frac_bits, cfg.out_bits
    z = np.arange(brdf.epicentre_codes(n, zf) + 1)
    out = brdf.evaluate(cfg, z, n)
    assert np.array_equal(out, brdf.evaluate(cfg, -z, n))
    value = out / 2.0**o
    d = z * math.pi / 2 / 2.0**zf
    f = brdf.approximate(cfg.form, d, n)
    ab = float(np.abs(value - np.clip(f, 0.0, 1 - 2.0**-o)).max()) * 2.0**o
    rel = np.where(f >= REL_FLOOR, np.abs(value / np.maximum(f, REL_FLOOR) - 1), 0.0).max()
    return ab, float(rel), float(np.abs(value / np.cos(d) ** n - 1).max())


@pytest.mark.parametrize("form", brdf.FORMS)
def test_the_walk_equals_a_brute_force_over_every_angle_code(form: str) -> None:
    cfg = brdf.FixedConfig(form, cos_addr_bits=9, cos_data_bits=16, angle=NARROW)
    acc = brdf.fixed_accuracy(cfg)
    for n in SOME_N:
        want = (acc.abs_lsb[n - 1], acc.rel[n - 1], acc.rel_cos[n - 1])
        assert _brute_force(cfg, n) == pytest.approx(want, rel=1e-12, abs=1e-15), n


@pytest.mark.parametrize("form", brdf.FORMS)
def test_every_form_falls_with_the_angle_over_the_epicentre(form: str) -> None:
    """What the walk needs: each float form is non-increasing in the angle there."""
    for n in range(1, N_MAX + 1):
        end = brdf.epicentre_codes(n, DEFAULT.z_frac_bits) * math.pi / 2 / 2.0**DEFAULT.z_frac_bits
        values = brdf.approximate(form, np.linspace(0.0, end, 257), n)
        assert np.all(np.diff(values) <= 0.0), n


@pytest.mark.parametrize("form", brdf.FORMS)
def test_random_angles_stay_within_the_worst_errors_found(form: str) -> None:
    cfg = brdf.CONFIGS[form]
    acc = brdf.fixed_accuracy(cfg)
    rng = np.random.default_rng(7)
    for n in rng.integers(1, N_MAX + 1, 40):
        n = int(n)
        z = rng.integers(0, brdf.epicentre_codes(n, DEFAULT.z_frac_bits) + 1, 500)
        value = brdf.evaluate(cfg, z, n) / 2.0**cfg.out_bits
        f = brdf.approximate(form, z * math.pi / 2 / 2.0**DEFAULT.z_frac_bits, n)
        lsb = np.abs(value - np.clip(f, 0.0, 1 - 2.0**-cfg.out_bits)) * 2.0**cfg.out_bits
        assert lsb.max() <= acc.abs_lsb[n - 1] * (1 + 1e-12)
        assert np.all(value >= 0.0) and np.all(value < 1.0)


@pytest.mark.parametrize("form", brdf.FORMS)
def test_the_ends_of_the_range_are_one_and_zero(form: str) -> None:
    """Full scale (2^O - 1, 1.0 saturated) at d = 0; from pi/2 on cos reads 0 and the form is 0
    (but the cosine-quadratic for n = 1, 2, whose zero lies beyond pi/2: (1 - 7n/16)^2)."""
    cfg = brdf.CONFIGS[form]
    top, one = (1 << cfg.out_bits) - 1, 1 << DEFAULT.z_frac_bits
    for n in SOME_N:
        at_zero, at_right, far = brdf.evaluate(cfg, [0, one, -3 * one], n)
        assert at_zero == top
        want = 0
        if form == "cosine_quadratic" and n <= 2:
            want = round((1 - 7 * n / 16) ** 2 * 2**cfg.out_bits)
        assert at_right == far == want


def test_the_piecewise_forms_bloom_part_divides_to_half_an_lsb() -> None:
    """Beyond the junction (cos^n < 0.5, outside the epicentre) the piecewise unit divides:
    at every angle-table address of the bloom zone the output is the float form at the
    address's angle to within its rounding, half an LSB, plus what the coefficient words add
    (r in Q11.7 is up to 0.08 % off at n = 3; 8-bit output, 24-bit table words exact to far below
    an output LSB there)."""
    cfg = brdf.FixedConfig("piecewise", cos_data_bits=24, work_bits=20, out_bits=8)
    z = np.arange(1 << cfg.cos_addr_bits) << cfg.addr_shift
    d = z * math.pi / 2 / 2.0**DEFAULT.z_frac_bits
    for n in SOME_N[1:]:
        bloom = np.cos(d) < 0.5 ** (1 / n)
        out = brdf.evaluate(cfg, z, n)
        f = brdf.approximate("piecewise", d, n) * 2**cfg.out_bits
        assert bloom.sum() > 100
        assert np.abs(out - f)[bloom].max() <= 0.6, n


def test_the_cubic_in_tau_is_the_thesiss_cubic() -> None:
    """The coefficient table's rewrite p0 + b1 tau + b2 tau^2, tau = 1 - r w, is the float
    cubic about s, and the bloom's s2 - beta' tau its denominator alpha - beta c."""
    c = np.linspace(0.0, 1.0, 101)
    for n in SOME_N:
        k = brdf.cubic_coefficients(n)
        r, p0, b1, b2, s2, beta = brdf.coefficient_values("piecewise", n)
        tau = 1 - r * (1 - c)
        want = c * (k.p0 + (c - k.cos_t) * (k.p1 + k.a1 * (c - k.cos_t)))
        scale = 1e-12 * (1 + np.abs(want).max())
        assert c * (p0 + tau * (b1 + b2 * tau)) == pytest.approx(want, abs=scale)
        b = brdf.bloom_coefficients(n)
        assert s2 - beta * tau == pytest.approx(b.alpha - b.beta * c, rel=1e-9, abs=1e-12)
        assert all(0.0 <= x <= 1.0 for x in (b1, b2)) and 0.5 <= p0 <= 1.0


@pytest.mark.parametrize("form", ["quadratic", "cubic", "piecewise"])
def test_coefficient_words_are_the_values_rounded_to_their_formats(form: str) -> None:
    cfg = brdf.CONFIGS[form]
    fracs = np.array([q.frac_bits for q in cfg.coef_formats.values()], dtype=np.float64)
    words = brdf.coefficient_words(cfg)
    assert words.max() < 1 << cfg.coef_bits
    for n in SOME_N:
        values = np.array(brdf.coefficient_values(form, n))
        assert np.all(np.abs(words[n - 1] - values * 2.0**fracs) <= 0.5)


# ------------------------------------------------------------------ tables and bits
@pytest.mark.parametrize("form", brdf.FORMS)
def test_table_bits_add_up_and_every_word_fits(form: str) -> None:
    cfg = brdf.CONFIGS[form]
    bits, images = brdf.table_bits(cfg), brdf.rom_images(cfg)
    widths = {"angle": cfg.cos_data_bits, "coef": cfg.coef_bits, "log2": cfg.log_data_bits}
    assert set(bits) == {*images, "total"}
    for name, words in images.items():
        assert bits[name] == words.size * widths[name]
        assert words.min() >= 0 and words.max() < 1 << widths[name]
    assert bits["total"] == sum(v for k, v in bits.items() if k != "total")
    assert images["angle"][0] == 0  # 1 - cos 0 and -log2 cos 0 are exact
    if "coef" in images:
        assert images["coef"].shape == (N_MAX, len(cfg.coefficients))


@pytest.mark.parametrize(
    ("field", "value", "legal"),
    [
        ("cos_addr_bits", 1, "2..16"),
        ("cos_data_bits", 25, "4..24"),
        ("coef_bits", 3, "4..32"),
        ("work_bits", 29, "4..28"),
        ("out_bits", 0, "1..24"),
        ("log_addr_bits", 17, "2..16"),
        ("log_data_bits", 2.5, "4..24"),
    ],
)
def test_a_bad_width_is_refused_by_name_value_and_range(field: str, value, legal: str) -> None:
    with pytest.raises(ValueError) as err:
        brdf.FixedConfig("cubic", **{field: value})
    assert str(err.value) == f"{field} = {value!r} is out of range: legal widths are {legal}"


def test_a_bad_form_angle_or_product_is_refused_by_name() -> None:
    with pytest.raises(ValueError, match=r"^form = 'cubik' is out of range: legal forms are"):
        brdf.FixedConfig("cubik")
    with pytest.raises(ValueError, match=r"^angle = 26 is out of range: legal is a SpecularC"):
        brdf.FixedConfig("cubic", angle=26)  # type: ignore[arg-type]
    narrow = SpecularConfig(z_frac_bits=10, a_frac_bits=14)
    with pytest.raises(ValueError, match=r"^cos_addr_bits = 12 is out of range: .* 2\.\.10$"):
        brdf.FixedConfig("cubic", angle=narrow)
    with pytest.raises(ValueError) as err:
        brdf.FixedConfig("cubic", work_bits=28)
    assert str(err.value) == "tau x (b1 + b2 tau) = 68 is out of range: at most 62 bits"


def test_evaluate_refuses_a_bad_n_or_angle() -> None:
    cfg = brdf.CONFIGS["quadratic"]
    with pytest.raises(ValueError, match=r"^n = 1001 is out of range: legal range is 1\.\.1000"):
        brdf.evaluate(cfg, [0], 1001)
    hi = (1 << (DEFAULT.acc_width - 1)) - 1
    with pytest.raises(ValueError, match=rf"^z = {hi + 1} is out of range"):
        brdf.evaluate(cfg, [hi + 1], 8)


# ------------------------------------------------------------------ the page
def _section(title: str) -> str:
    text = PAGE.read_text()
    start = text.index(f"## {title}")
    end = text.find("\n## ", start + 1)
    return text[start : None if end < 0 else end]


def test_the_page_shows_the_fixed_table_the_code_computes() -> None:
    assert brdf.format_fixed_table() in _section("Fixed point"), (
        "docs/brdf.md: the fixed-point table is stale (python scripts/brdf_budget.py)"
    )


WINNER_RANGES = ((1, 1, 1), (2, 2, 2), (3, 21, 11), (22, 1000, 36))


def test_the_winner_the_page_names_fits_the_budget_and_its_figures_hold() -> None:
    """Quick: the winner's k set fits the patent's budget (computed from the patent's unit),
    and its float and fixed-point worst over n = 8..1000 are the page's, both under 0.15 %."""
    assert budget.budget_bits() == DEFAULT.rom9_bits + DEFAULT.rom12_bits
    cfg = SpecularConfig(k_ranges=WINNER_RANGES, alpha="inflection")
    assert cfg.rom_bits <= budget.budget_bits()
    worst = float(float_errors(cfg)[7:].max())
    fixed_worst = float(fixed_point_accuracy(cfg).rom_rel[7:].max())
    assert max(worst, fixed_worst) <= 0.0015
    line = next(x for x in _section("Beyond").splitlines() if x.startswith("winner: "))
    figures = re.findall(r"(\d+\.\d{4}) %", line)
    assert figures == [brdf.format_error(worst)[:-2], brdf.format_error(fixed_worst)[:-2]]
    assert "k = 1..1: 1, 2..2: 2, 3..21: 11, 22..1000: 36" in line


def _figures(text: str) -> set[str]:
    return set(re.findall(r"\d+\.\d{4} %", text))


def test_the_fixed_point_sections_figures_are_the_scripts() -> None:
    """Every four-decimal figure of the section's prose is one of its table's."""
    section = _section("Fixed point")
    assert _figures(section) <= _figures(brdf.format_fixed_table())


def test_the_page_shows_the_budget_table_the_search_prints(capsys, tmp_path: Path) -> None:
    """The whole search, once (about 20 s: the candidates' ROM-12 errors come from
    ``specular.rom_rel_errors``, the walk stopped at the epicentre's end): through the script,
    which prints both tables and writes the JSON, then the page against what it printed."""
    import importlib.util
    import json

    spec = importlib.util.spec_from_file_location("brdf_budget", ROOT / "scripts/brdf_budget.py")
    assert spec is not None and spec.loader is not None
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    path = tmp_path / "budget.json"
    assert script.main(["--json", str(path)]) == 0
    printed = capsys.readouterr().out
    assert brdf.format_fixed_table() in printed and brdf.format_budget_table() in printed
    data = json.loads(path.read_text())
    assert data["budget_bits"] == budget.budget_bits()
    assert len(data["candidates"]) == len(brdf.candidates())
    table = brdf.format_budget_table()
    section = _section("Beyond")
    assert table in section, "docs/brdf.md: stale budget table (brdf_budget.py)"
    assert _figures(section) <= _figures(table)  # the prose quotes the table only
    best = brdf.winner()
    assert best.fits and best.config.k_ranges == WINNER_RANGES
    assert all(c.fits for c in brdf.candidates())
    assert brdf.best_k_ranges(4, "inflection", 12, budget.SMALL_N_TABLES, True) == WINNER_RANGES


def test_the_angle_tables_step_is_what_costs_accuracy_at_large_n() -> None:
    """At n = 1000 the address rounding dominates: one address bit less nearly doubles the
    error, four more (A = 16) cut it by more than 4 (what is left is the 20-bit words)."""
    base = brdf.CONFIGS["cosine_quadratic"]
    errors = [
        brdf.fixed_accuracy(replace(base, cos_addr_bits=a)).rel[N_MAX - 1] for a in (11, 12, 16)
    ]
    assert errors[0] > 1.5 * errors[1] > 1.5 * 4 * errors[2]
