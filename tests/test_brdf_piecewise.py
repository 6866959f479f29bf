# SPDX-License-Identifier: Apache-2.0
"""The piecewise form's datapath widths (rtl/brdf_piecewise.v's header, its proofs 1-8) hold,
and its divider's route to the model's quotient is the model's.

For every n = 1..1000 and every word of the angle table (and 2^D, the front's cos = 0), in the
integer steps rtl/brdf_piecewise.v takes: rw = round(r w) <= 2^(P+11); the bloom branch
(rw >= 2^P) has w >= 1; the table's s2 rounds to at least 2^P (s2 >= 1); 2^P <= den <
2^(P+13); the divider's quotient a = (2 num) // den' is below 2^(O+1) (its O + 1 stages) and
(a + 1) >> 1 is the model's (2 num + den') // (2 den'); the result equals
``fixed.evaluate`` word for word.  Also: which quotient bits the tables reach (at the default
widths bit O never, at others it does: the O + 1 stages are needed), and the identity
(2 x + y) // (2 y) = ((2 x) // y + 1) >> 1 on random and small integers.
"""

from __future__ import annotations

import random

import numpy as np
import pytest

from model.units import brdf, specular
from model.units.brdf import FixedConfig

# The default widths, and widths where the quotient's bit O is reached (11-bit coefficients:
# s2 rounded to 10 fraction bits) and where den is shifted up instead of c (P + O < D)
CONFIGS = {
    "default": brdf.UNIT_CONFIGS["piecewise"],
    "coef11": FixedConfig("piecewise", coef_bits=11, work_bits=8, out_bits=12),
    "den_shift": FixedConfig("piecewise", cos_data_bits=20, coef_bits=21, work_bits=8, out_bits=4),
}


def _round(x: np.ndarray, shift: int) -> np.ndarray:
    """Add half, slice (int64); a shift of 0 or less scales exactly."""
    return x << -shift if shift <= 0 else (x + (1 << (shift - 1))) >> shift


def _walk(cfg: FixedConfig) -> dict[str, int]:
    """Every (n, angle word) through the RTL's integer steps, each bound asserted; returns the
    counts and extremes the test checks."""
    d, p, o, c_bits = cfg.cos_data_bits, cfg.work_bits, cfg.out_bits, cfg.coef_bits
    w = np.append(brdf.angle_table(cfg), 1 << d).astype(np.int64)
    addr = np.arange(w.size, dtype=np.int64)  # w.size - 1: the front's 2^D (pi/2 and beyond)
    z = np.minimum(addr, (1 << cfg.cos_addr_bits)) << cfg.addr_shift
    coef = brdf.coefficient_words(cfg)
    ns, ds = max(0, p + o - d), max(0, d - p - o)
    seen = {"bloom": 0, "cubic": 0, "a_bit_o": 0, "max_a": 0}
    for n in range(1, specular.N_MAX + 1):
        r, _, _, _, s2, beta = (int(v) for v in coef[n - 1])
        rw = _round(r * w, c_bits - brdf.CUBIC_R_INT_BITS + d - p)
        assert rw.max() <= 1 << (p + 11), n  # 1.
        bloom = rw >= 1 << p
        assert (w[bloom] >= 1).all(), n  # 5.
        s2r = int(_round(np.int64(s2), c_bits - 1 - p))
        assert 1 << p <= s2r <= 1 << (p + 1), n  # 3.
        rwm = rw[bloom] - (1 << p)
        assert (rwm < 1 << (p + 11)).all()  # 1., the bloom branch
        den = s2r + _round(beta * rwm, c_bits - 1)
        assert (den >= 1 << p).all() and (den < 1 << (p + 13)).all(), n  # 4.
        num = ((1 << d) - w[bloom]) << ns
        a = (2 * num) // (den << ds)
        assert (a < 1 << (o + 1)).all(), n  # 6.
        q = (2 * num + (den << ds)) // (2 * (den << ds))
        assert ((a + 1) >> 1 == q).all(), n  # 6., the identity
        want = np.minimum(q, (1 << o) - 1)
        got = brdf.evaluate(cfg, z[bloom], n)
        assert (got == want).all(), n  # the model's words
        seen["bloom"] += int(bloom.sum())
        seen["cubic"] += int((~bloom).sum())
        seen["a_bit_o"] += int((a >> o).sum())
        seen["max_a"] = max(seen["max_a"], int(a.max(initial=0)))
    return seen


@pytest.mark.parametrize("name", list(CONFIGS))
def test_piecewise_widths_hold_on_the_table(name: str) -> None:
    """Proofs 1-6 of rtl/brdf_piecewise.v on every (n, angle word) of the tables; both branches
    are reached.  At the default widths the bloom part never reaches 1/2 (a < 2^O: bit O of
    the quotient stays 0, q <= 2^(O-1)); with 11-bit coefficients it does, so the divider
    keeps O + 1 quotient bits for every legal width."""
    cfg = CONFIGS[name]
    seen = _walk(cfg)
    assert seen["bloom"] > 1000 * 1000 and seen["cubic"] > 1000 * 50, seen
    if name == "default":
        assert seen["a_bit_o"] == 0 and seen["max_a"] >= 1 << (cfg.out_bits - 1), seen
    if name == "coef11":
        assert seen["a_bit_o"] > 0, seen


def test_the_divider_rounds_as_the_model() -> None:
    """(2 x + y) // (2 y) == ((2 x) // y + 1) >> 1 for any x >= 0, y > 0: 2 x = a y + r with
    0 <= r < y puts (2 x + y) / (2 y) at (a + 1) / 2 + r / (2 y), r / (2 y) < 1/2."""
    rng = random.Random("brdf-piecewise-divide")
    for _ in range(20000):
        y = rng.randint(1, 1 << rng.randint(1, 40))
        x = rng.randint(0, y << rng.randint(0, 25))
        assert (2 * x + y) // (2 * y) == ((2 * x) // y + 1) >> 1, (x, y)
    for y in range(1, 40):
        for x in range(0, 4 * y):
            assert (2 * x + y) // (2 * y) == ((2 * x) // y + 1) >> 1, (x, y)


def test_the_bloom_part_falls_slower_than_cos_n() -> None:
    """docs/scenes.md, method (m): at n = 40 (the teapot's), where cos^n is 0.01, the piecewise
    form's bloom part c / (alpha - beta c) is still 0.0979; at the junction both are 1/2."""
    n = 40
    at = np.arccos(np.array([0.01 ** (1 / n), 0.5 ** (1 / n)]))
    bloom, junction = brdf.approximate("piecewise", at, n)
    assert f"{bloom:.4f}" == "0.0979" and junction == pytest.approx(0.5, abs=1e-12)
