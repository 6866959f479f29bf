# SPDX-License-Identifier: Apache-2.0
"""The thesis's BRDF family (model.units.brdf): coefficients meet their conditions, the exact
worst errors are not beaten by a dense sample and are reached by it, the claims table is the
one docs/brdf.md shows, and a bad n is refused by name."""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.special import lambertw

from model.units import brdf
from model.units.specular import ALPHA_MODES, N_MAX, alpha_value, brdf_max_rel_error, epicentre

ROOT = Path(__file__).resolve().parent.parent
SOME_N = (1, 2, 3, 4, 7, 10, 25, 100, 276, 999, 1000)
SAMPLES = 4097  # points per n of the dense sample over the epicentre


def _cos_power_slope(c: float, n: int, level: float) -> float:
    """d/dc of c^n at the c where c^n = level: n level / c."""
    return n * level / c


# ------------------------------------------------------------------ coefficients
@pytest.mark.parametrize("n", SOME_N)
def test_quadratic_is_one_at_zero_and_meets_cos_power_at_the_epicentre_end(n: int) -> None:
    k = brdf.quadratic_coefficients(n)
    assert k.a + k.b == pytest.approx(1.0, abs=1e-15)  # c = 0 is built in (no constant)
    u = math.sqrt((n - 1) / n)
    q = ((n - 1) / n) ** (n / 2)  # the inflection level, reached at cos = u
    assert k.a * u * u + k.b * u == pytest.approx(q, abs=1e-13)
    if n >= 2:
        assert k.a == pytest.approx((u - q) / (u * (1 - u)), rel=1e-12)
    d_end = np.array([epicentre(n)])
    assert brdf.approximate("quadratic", np.array([0.0]), n)[0] == pytest.approx(1.0)
    assert brdf.approximate("quadratic", d_end, n)[0] == pytest.approx(np.cos(d_end[0]) ** n)


def _slope_in_delta(form: str, d: float, n: int) -> float:
    """d/d(delta) of the form at d, by a central difference."""
    h = 1e-6 * d
    up, down = brdf.approximate(form, np.array([d + h, d - h]), n)
    return (up - down) / (2 * h)


@pytest.mark.parametrize("n", SOME_N)
def test_cubic_meets_cos_power_at_zero_and_in_value_and_slope_at_half(n: int) -> None:
    k = brdf.cubic_coefficients(n)
    s = 0.5 ** (1 / n)
    assert k.d1 == 0.0 and k.cos_t == pytest.approx(s, rel=1e-15)
    # The thesis's monomial coefficients: the conditions hold up to their own cancellation.
    scale = 1e-14 * (abs(k.a1) + abs(k.b1) + abs(k.c1))
    assert k.a1 + k.b1 + k.c1 == pytest.approx(1.0, abs=scale)
    assert k.a1 * s**3 + k.b1 * s**2 + k.c1 * s == pytest.approx(0.5, abs=scale)
    slope = 3 * k.a1 * s**2 + 2 * k.b1 * s + k.c1
    assert slope == pytest.approx(_cos_power_slope(s, n, 0.5), abs=10 * scale)
    # The float form (evaluated about s): the same conditions to float precision.
    t = math.acos(s)
    at_0, at_t = brdf.approximate("cubic", np.array([0.0, t]), n)
    assert at_0 == pytest.approx(1.0, abs=1e-14) and at_t == pytest.approx(0.5, abs=1e-14)
    if n > 1:
        want = -n * math.cos(t) ** (n - 1) * math.sin(t)
        assert _slope_in_delta("cubic", t, n) == pytest.approx(want, rel=1e-6)
    if n in (1, 2, 3):  # cos^n itself is in the span: the fit is exact
        want = {1: (0, 0, 1), 2: (0, 1, 0), 3: (1, 0, 0)}[n]
        assert (k.a1, k.b1, k.c1) == pytest.approx(want, abs=1e-12)


@pytest.mark.parametrize("n", SOME_N)
def test_bloom_meets_the_cubic_in_value_and_slope_and_beta_is_the_theses(n: int) -> None:
    b = brdf.bloom_coefficients(n)
    s = 0.5 ** (1 / n)
    assert b.beta == 2 * (n - 1)  # the OCR's beta = 2(n - 1)
    assert b.alpha == pytest.approx(2 * n * 0.5 ** (1 / n), rel=1e-15)
    assert s / (b.alpha - b.beta * s) == pytest.approx(0.5, rel=1e-12)
    slope = b.alpha / (b.alpha - b.beta * s) ** 2
    assert slope == pytest.approx(_cos_power_slope(s, n, 0.5), rel=1e-9)
    t = math.acos(s)  # the two parts join there: no step in the piecewise form
    left, right = brdf.approximate("piecewise", np.array([t * (1 - 1e-9), t * (1 + 1e-9)]), n)
    assert left == pytest.approx(right, abs=1e-6)
    if n > 1:  # and no kink: the bloom part's slope just past t is the cubic's just before
        h = 1e-4 * t
        assert _slope_in_delta("piecewise", t + h, n) == pytest.approx(
            _slope_in_delta("piecewise", t - h, n), rel=1e-3
        )


@pytest.mark.parametrize("n", (3, 7, 25, 1000))
def test_cosine_quadratic_starts_at_one_and_ends_with_its_zero_and_curvature(n: int) -> None:
    m = brdf.cosine_quadratic_scale(n)
    assert m == 7 * n / 16
    d0 = math.acos(1 - 16 / (7 * n))
    values = brdf.approximate("cosine_quadratic", np.array([0.0, d0, d0 + 1e-3, 1.5]), n)
    assert values[0] == 1.0 and values[1] == pytest.approx(0.0, abs=1e-24)
    assert values[2] == values[3] == 0.0
    # The graph's radius of curvature at the zero: A'' = 2 m^2 sin^2 d0 there (A' = 0).
    h = 1e-5 * d0
    a_left = brdf.approximate("cosine_quadratic", np.array([d0 - h]), n)[0]
    radius = 1 / (2 * a_left / h**2)
    assert radius == pytest.approx(4 / (7 * n - 8), rel=1e-4)


def test_the_log_forms_2x_is_exact_at_the_epicentres_ends_of_x() -> None:
    assert brdf.exp2_approx(np.array([0.0, -1.0, -3.0, -10.0])).tolist() == [1.0, 0.5, 0.0, 0.0]
    x = np.linspace(-1, 0, 10001)
    assert np.max(np.abs(brdf.exp2_approx(x) / 2**x - 1)) < 0.0030


def test_the_log_forms_peak_is_the_theses_lambert_w_point() -> None:
    """delta = arccos(e^eps), eps = (1 + ln2 W) / (n W), W = W0(-1/(4 ln2)) (the positive
    peak, inside the epicentre for n = 2..7); W_-1 gives the negative one."""
    ln2 = math.log(2)
    w0 = lambertw(-1 / (4 * ln2), 0).real
    w1 = lambertw(-1 / (4 * ln2), -1).real
    for n in range(2, 8):
        peak = brdf.max_rel_error("log2", n)
        want = math.acos(math.exp((1 + ln2 * w0) / (n * w0)))
        assert peak.delta == pytest.approx(want, rel=1e-7)
        d_neg = math.acos(math.exp((1 + ln2 * w1) / (n * w1)))
        neg = brdf.approximate("log2", np.array([d_neg]), n)[0] / math.cos(d_neg) ** n - 1
        assert -0.0024 < neg < -0.0023 and abs(neg) < peak.error
    y_peak = -1 / (ln2 * w0) - 1  # -x at the peak: outside the epicentre from n = 8 on
    assert -4 * math.log2(7 / 8) < y_peak < -3.5 * math.log2(6 / 7)


def test_the_inflection_alpha_is_the_one_matched_at_the_inflection_point() -> None:
    assert "inflection" in ALPHA_MODES
    for n, k in ((10, 2), (10, 3), (500, 3)):
        d = epicentre(n)
        assert math.cos(alpha_value(n, k, "inflection") * d) ** k == pytest.approx(
            math.cos(d) ** n, rel=1e-12
        )


# ------------------------------------------------------------------ exact worst errors
def _sample_max(form: str, n: int, level: float | None) -> float:
    d_end = epicentre(n) if level is None else math.acos(level ** (1 / n))
    d = np.linspace(0.0, d_end, SAMPLES)
    return float(np.max(np.abs(brdf.approximate(form, d, n) / np.cos(d) ** n - 1)))


@pytest.mark.parametrize(
    ("form", "level"), [*((f, None) for f in brdf.FORMS), ("piecewise", brdf.INV_E)]
)
def test_a_dense_sample_never_beats_the_exact_maximum_and_comes_close(
    form: str, level: float | None
) -> None:
    exact = brdf.worst_errors(form, level)
    sample = np.array([_sample_max(form, n, level) for n in range(1, N_MAX + 1)])
    noise = 1e-14 + 1e-12 * exact
    over = np.flatnonzero(sample > exact + noise)
    assert over.size == 0, f"{form}: sample above the exact maximum at n = {over[:5] + 1}"
    short = np.flatnonzero(sample < exact * (1 - 1e-6) - 1e-14)
    assert short.size == 0, f"{form}: sample far below the exact maximum at n = {short[:5] + 1}"


def test_the_piecewise_form_is_the_cubic_over_the_epicentre() -> None:
    """cos^n >= 0.5 over the whole epicentre (its end's level ((n-1)/n)^(n/2) is 0.5 at n = 2
    and grows), so the bloom part never enters it but at n = 1, where it is cos itself."""
    assert np.array_equal(brdf.worst_errors("piecewise")[1:], brdf.worst_errors("cubic")[1:])


def test_the_epicentre_end_is_a_candidate_for_n_1_as_in_the_specular_model() -> None:
    """n = 1: the range ends at the float pi/2 (cos = 6e-17), as brdf_max_rel_error's does."""
    assert brdf_max_rel_error(1, 1) == 0.0
    for form in ("quadratic", "cubic", "piecewise"):
        assert brdf.max_rel_error(form, 1).error == 0.0  # each is cos itself at n = 1
    assert brdf.max_rel_error("log2", 1) == brdf.Peak(1.0, math.pi / 2)  # 2^x ~ 0 at x = -54
    peak = brdf.max_rel_error("cosine_quadratic", 1)
    assert peak.delta == math.pi / 2 and peak.error == pytest.approx((9 / 16) ** 2 / 6.1e-17, 0.01)


# ------------------------------------------------------------------ the claims and the page
def _script():
    spec = importlib.util.spec_from_file_location("brdf_claims", ROOT / "scripts/brdf_claims.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_page_shows_the_table_the_script_prints(capsys, tmp_path: Path) -> None:
    out = tmp_path / "brdf.json"
    assert _script().main(["--json", str(out)]) == 0
    printed = capsys.readouterr().out.strip()
    assert printed == brdf.format_claims_table()
    page = (ROOT / "docs/brdf.md").read_text()
    assert printed in page, "docs/brdf.md: the table is stale (python scripts/brdf_claims.py)"
    records = json.loads(out.read_text())
    assert [r["label"] for r in records] == [c.label for c in brdf.CLAIMS]
    for record, check in zip(records, brdf.check_claims(), strict=True):
        assert record["worst"] == check.worst[0] and record["failing_n"] == check.failing
        assert len(record["errors"]) == N_MAX


def test_the_claims_that_fail_fail_where_the_page_says() -> None:
    fails = {(c.claim.form, c.claim.percent, c.claim.level): c.failing for c in brdf.check_claims()}
    assert fails[("quadratic", "3.14", None)] == list(range(276, N_MAX + 1))
    assert fails[("cubic", "0.67", None)] == list(range(115, N_MAX + 1))
    assert fails[("piecewise", "4", None)] == fails[("piecewise", "4", brdf.INV_E)] == []
    assert fails[("log2", "0.29", None)] == list(range(1, 12))
    assert fails[("cosine_quadratic", "2", None)] == list(range(25, 38))
    assert fails[("cosine_quadratic", "3", None)] == list(range(1, 6))


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize("n", [0, -3, N_MAX + 1, 2.5])
@pytest.mark.parametrize(
    "call",
    [
        brdf.quadratic_coefficients,
        brdf.cubic_coefficients,
        brdf.bloom_coefficients,
        brdf.cosine_quadratic_scale,
        lambda n: brdf.approximate("log2", np.zeros(3), n),
        lambda n: brdf.max_rel_error("cubic", n),
    ],
)
def test_a_bad_n_is_refused_by_name_value_and_range(call, n) -> None:
    with pytest.raises(ValueError, match=r"^n (= |must be an integer, got )") as caught:
        call(n)
    message = str(caught.value)
    assert f"{n:g}" in message and f"legal range is 1..{N_MAX}" in message, message


def test_a_bad_form_level_or_q_is_refused_by_name() -> None:
    with pytest.raises(ValueError, match=r"form = 'cubic2' is out of range: legal forms are"):
        brdf.max_rel_error("cubic2", 10)
    with pytest.raises(ValueError, match=r"level = 1.5 is out of range: legal is 0 < level < 1"):
        brdf.max_rel_error("cubic", 10, 1.5)
    with pytest.raises(ValueError, match=r"q = 0.0 is out of range: legal is 0 < q < 1"):
        brdf.cubic_coefficients(10, 0.0)
