# SPDX-License-Identifier: Apache-2.0
"""BRDF family: the thesis's float approximations of cos^n d and their exact worst errors.

Owns the five forms of the thesis's chapter 2 besides the patent's cos^k(a d) (``FORMS``): the
quadratic ``a cos^2 + b cos``, the cubic of the first approach, the piecewise cubic-and-bloom
form, the logarithmic form ``1 - log2(1 - n log2 cos)/2`` and the cosine-quadratic
``(1 - (7n/16)(1 - cos))^2``; each one's coefficients as a function of n
(``quadratic_coefficients``, ``cubic_coefficients``, ``bloom_coefficients``,
``cosine_quadratic_scale``), its float value (``approximate``, numpy, delta in radians) and the
certified maximum of its relative error in the highlight's epicentre (``max_rel_error``,
``worst_errors``).  No fixed-point arithmetic and no hardware: it measures the thesis's ideas.
May import numpy, ``model.units.fixed`` and ``model.units.specular``'s public names.

Every form is a function of c = cos d only, so the errors are found in c: the epicentre
d in [0, arctan(1/sqrt(n-1))] is c in [sqrt((n-1)/n), 1] (for n = 1 it ends at the float pi/2,
where cos is 6e-17, not 0, as ``model.units.specular.brdf_max_rel_error`` does).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from model.units import fixed
from model.units.specular import N_MAX, epicentre

FORMS = ("quadratic", "cubic", "piecewise", "log2", "cosine_quadratic")
"""The forms ``approximate`` and ``max_rel_error`` know, in the thesis's order."""
CUBIC_Q = 0.5
"""The cubic's match level: equal to cos^n in value and slope where cos^n = Q (the thesis's
choice, which also fixes the piecewise form's junction)."""
GRID = 64
"""Cells each monotone piece of the error's slope is cut into before bisection (a second guard:
the pieces alone already hold at most one root each, ``max_rel_error`` says why)."""


def check_n(n: int) -> int:
    """``n`` as an int, or ``ValueError`` naming it, its value and the legal range 1..N_MAX."""
    return int(fixed.check_operand("n", n, 1, N_MAX))


def _check_form(form: str) -> None:
    if form not in FORMS:
        raise ValueError(f"form = {form!r} is out of range: legal forms are {FORMS}")


# ==================================================================== coefficients
@dataclass(frozen=True)
class Quadratic:
    """``a c^2 + b c`` (c = cos d; the constant term is 0)."""

    a: float
    b: float


def quadratic_coefficients(n: int) -> Quadratic:
    """The quadratic a cos^2 + b cos + c matched to cos^n at the inflection level.

    cos^n = 1 at d = 0 and 0 where cos = 0 give c = 0 and b = 1 - a; equal to cos^n at the
    ordinate level q, where cos = u = q^(1/n): a = (u - q) / (u (1 - u)).  With q the inflection
    level ((n-1)/n)^(n/2), u = sqrt((n-1)/n) is the epicentre's end.  Computed as
    a = (1 - u^(n-1)) / (1 - u) (the same for n >= 2, q / u = u^(n-1)) with
    1 - u = (1/n) / (1 + u) and 1 - u^(n-1) = -expm1((n-1)/2 ln(1 - 1/n)), free of
    cancellation; at n = 1 the limit (u -> 0, u^(n-1) -> 1) is a = 0, b = 1: cos itself.
    """
    n = check_n(n)
    if n == 1:
        return Quadratic(0.0, 1.0)
    u = math.sqrt((n - 1) / n)
    a = -math.expm1((n - 1) / 2 * math.log1p(-1.0 / n)) * n * (1.0 + u)
    return Quadratic(a, 1.0 - a)


@dataclass(frozen=True)
class Cubic:
    """``a1 c^3 + b1 c^2 + c1 c + d1`` (c = cos d; d1 = 0), matched at c = ``cos_t`` = s.

    The same polynomial about s, c (p0 + p1 (c - s) + a1 (c - s)^2), is how it is evaluated:
    the monomial coefficients grow like n^2 (a1 = 3.2e5 at n = 1000) and cancel."""

    a1: float
    b1: float
    c1: float
    d1: float
    cos_t: float
    p0: float
    p1: float


def cubic_coefficients(n: int, q: float = CUBIC_Q) -> Cubic:
    """The cubic of the thesis's first approach: equal to cos^n at d = 0 (c = 1) and, in value
    and slope, at t where cos^n t = q; d1 = 0 (0 where cos = 0, like cos^n).

    With s = cos t = q^(1/n) and the cubic written c P(c), P quadratic: P(1) = 1,
    P(s) = q / s, and the slope (d/dc (c P) = n c^(n-1) at s) gives P'(s) = (n-1) q / s^2.  So
    P(c) = p0 + p1 (c - s) + a1 (c - s)^2 with p0 = q / s, p1 = (n-1) q / s^2 and
    a1 = (1 - p0 - p1 (1 - s)) / (1 - s)^2 (1 - s exact in float for the float s); expanded,
    b1 = p1 - 2 a1 s and c1 = p0 - p1 s + a1 s^2.  For q = 0.5: p0 = 0.5^(1 - 1/n),
    p1 = (n-1) 0.5^(1 - 2/n).  (Equal slopes in d and in c are the same condition: both sides
    are functions of cos d.)  For n = 1 this is cos itself (a1 = b1 = 0, c1 = 1); for n = 2, 3
    it is cos^n itself.
    """
    n = check_n(n)
    if not 0.0 < q < 1.0:
        raise ValueError(f"q = {q!r} is out of range: legal is 0 < q < 1")
    s = q ** (1.0 / n)
    one_minus_s = 1.0 - s  # exact for s >= 1/2 (Sterbenz): conditions hold about the float s
    p0, p1 = q / s, (n - 1) * q / s**2
    a1 = (1.0 - p0 - p1 * one_minus_s) / one_minus_s**2
    return Cubic(a1, p1 - 2.0 * a1 * s, p0 - p1 * s + a1 * s * s, 0.0, s, p0, p1)


@dataclass(frozen=True)
class Bloom:
    """``c / (alpha - beta c)`` (c = cos d), the piecewise form's bloom part for c <= ``cos_t``."""

    alpha: float
    beta: float
    cos_t: float


def bloom_coefficients(n: int) -> Bloom:
    """alpha, beta of the bloom part c / (alpha - beta c), equal to cos^n (and so to the cubic
    of ``cubic_coefficients``) in value and slope at d = arccos(0.5^(1/n)), c = s = 0.5^(1/n).

    Value: s / (alpha - beta s) = 1/2, so alpha - beta s = 2 s.  Slope:
    d/dc [c / (alpha - beta c)] = alpha / (alpha - beta c)^2, equal to n s^(n-1) = n / (2 s)
    at s: alpha / (2 s)^2 = n / (2 s), alpha = 2 n s = 2 n 0.5^(1/n); then
    beta = (alpha - 2 s) / s = 2 (n - 1), the OCR's beta.  For n = 1: alpha = 1, beta = 0 (cos).
    """
    n = check_n(n)
    s = CUBIC_Q ** (1.0 / n)
    return Bloom(2.0 * n * s, 2.0 * (n - 1), s)


def _bloom_denominator(c: np.ndarray, bloom: Bloom) -> np.ndarray:
    """alpha - beta c, as 2 s + beta (s - c) (alpha and beta c cancel: 2000 - 1998 at n = 1000)."""
    return 2.0 * bloom.cos_t + bloom.beta * (bloom.cos_t - c)


def cosine_quadratic_scale(n: int) -> float:
    """m = 7n/16 of the cosine-quadratic (1 - m (1 - cos d))^2: equal to cos^n at d = 0, 0 from
    d = arccos(1 - 16/(7n)) on."""
    return 7.0 * check_n(n) / 16.0


def exp2_approx(x: np.ndarray) -> np.ndarray:
    """The logarithmic form's 2^x for x <= 0: 1 - log2(1 - x) / 2, 0 from x = -3 on.

    Exact at x = 0 and x = -1 (the epicentre's x = n log2 cos d lies in [-1, 0]); it needs a
    second log2 (of 1 - x), the same operation as the tabulated log2 cos, so one log2 device
    serves both steps (fig. 9b)."""
    x = np.asarray(x, dtype=np.float64)
    return np.maximum(0.0, 1.0 - np.log2(1.0 - x) / 2.0)


# ==================================================================== the forms, in c = cos d
def _quadratic_c(c: np.ndarray, n: int) -> np.ndarray:
    k = quadratic_coefficients(n)
    return np.maximum(0.0, c * (1.0 - k.a * (1.0 - c)))  # a c^2 + (1 - a) c


def _cubic_c(c: np.ndarray, n: int) -> np.ndarray:
    k = cubic_coefficients(n)
    t = c - k.cos_t
    return np.maximum(0.0, c * (k.p0 + t * (k.p1 + k.a1 * t)))


def _piecewise_c(c: np.ndarray, n: int) -> np.ndarray:
    bloom = bloom_coefficients(n)
    return np.where(c > bloom.cos_t, _cubic_c(c, n), c / _bloom_denominator(c, bloom))


def _log2_c(c: np.ndarray, n: int) -> np.ndarray:
    with np.errstate(divide="ignore"):  # log2(0) = -inf: x = -inf, the form is 0
        return exp2_approx(n * np.log2(c))


def _cosine_quadratic_c(c: np.ndarray, n: int) -> np.ndarray:
    return np.maximum(0.0, 1.0 - cosine_quadratic_scale(n) * (1.0 - c)) ** 2


_OF_COS: dict[str, Callable[[np.ndarray, int], np.ndarray]] = {
    "quadratic": _quadratic_c,
    "cubic": _cubic_c,
    "piecewise": _piecewise_c,
    "log2": _log2_c,
    "cosine_quadratic": _cosine_quadratic_c,
}


def approximate(form: str, delta: np.ndarray, n: int) -> np.ndarray:
    """The float value of ``form`` (one of ``FORMS``) at the angles ``delta`` (radians) for n.

    Every form is a function of c = cos(min(|delta|, pi/2)) (at the float pi/2 cos is 6e-17,
    as cos^n sees it), clipped at 0 where its formula turns negative (an intensity is never
    negative; inside the epicentre none of them does):
    * ``quadratic``: a c^2 + b c (``quadratic_coefficients``);
    * ``cubic``: a1 c^3 + b1 c^2 + c1 c (``cubic_coefficients``, Q = 0.5);
    * ``piecewise``: that cubic where cos^n > 0.5 (c > 0.5^(1/n)), c / (alpha - beta c)
      (``bloom_coefficients``) where cos^n <= 0.5;
    * ``log2``: 2^(n log2 c) with 2^x ~ 1 - log2(1 - x)/2 (``exp2_approx``);
    * ``cosine_quadratic``: (1 - (7n/16)(1 - c))^2, 0 where the base is negative.
    """
    _check_form(form)
    n = check_n(n)
    c = np.cos(np.minimum(np.abs(np.asarray(delta, dtype=np.float64)), np.pi / 2))
    return _OF_COS[form](c, n)


# ==================================================================== exact worst errors
@dataclass(frozen=True)
class Peak:
    """The largest |approx / cos^n - 1| on a range and an angle where it is reached."""

    error: float
    delta: float


Slope = Callable[[np.ndarray], np.ndarray]


def _quadratic_slope(n: int) -> tuple[Slope, list[float]]:
    k = quadratic_coefficients(n)
    zero = (k.a - 1.0) / k.a if k.a > 1.0 else 0.0  # A = c w, w = 1 - a (1 - c) = 0

    def slope(c: np.ndarray) -> np.ndarray:
        w = 1.0 - k.a * (1.0 - c)
        return np.where(c > zero, (1 - n) * w + k.a * c, 0.0)  # D / c

    return slope, [zero]


def _cubic_slope(n: int) -> tuple[Slope, list[float]]:
    k = cubic_coefficients(n)
    # D / c = (1 - n) P + c P' = t (C1 + C2 t) about t = c - s (the constant term is 0: s is
    # the tangency), C2 = (3 - n) a1, C1 = (2 - n) p1 + 2 a1 s.
    c2, c1 = (3 - n) * k.a1, (2 - n) * k.p1 + 2.0 * k.a1 * k.cos_t
    cuts = [k.cos_t + float(r.real) for r in np.roots((k.a1, k.p1, k.p0)) if r.imag == 0.0]
    if c2 != 0.0:
        cuts.append(k.cos_t - c1 / (2.0 * c2))  # the vertex of D / c

    def slope(c: np.ndarray) -> np.ndarray:
        t = c - k.cos_t
        return np.where(_cubic_c(c, n) > 0.0, t * (c1 + c2 * t), 0.0)

    return slope, cuts


def _piecewise_slope(n: int) -> tuple[Slope, list[float]]:
    cubic, cuts = _cubic_slope(n)
    s = bloom_coefficients(n).cos_t

    def slope(c: np.ndarray) -> np.ndarray:
        # the bloom part: D / c = (alpha (1 - n) + n beta c) / (...)^2 = 2 n (n - 1) (c - s) / ...
        return np.where(c > s, cubic(c), (n - 1) * (c - s))

    return slope, [s, *(x for x in cuts if x > s)]


def _log2_slope(n: int) -> tuple[Slope, list[float]]:
    ln2 = math.log(2.0)

    def slope(c: np.ndarray) -> np.ndarray:
        with np.errstate(divide="ignore", invalid="ignore"):
            u = 1.0 - n * np.log2(c)
            return np.where(u < 4.0, ln2 * u - u * np.log(u) / 2.0 - 1.0 / (2.0 * ln2), 0.0)

    # u = 4/e (the maximum of g) and u = 4 (A = 0 beyond), as c = 2^((1 - u) / n)
    return slope, [2.0 ** ((1.0 - 4.0 / math.e) / n), 2.0 ** (-3.0 / n)]


def _cosine_quadratic_slope(n: int) -> tuple[Slope, list[float]]:
    m = cosine_quadratic_scale(n)
    zero = 1.0 - 1.0 / m  # w = 1 - m (1 - c) = 0

    def slope(c: np.ndarray) -> np.ndarray:
        w = 1.0 - m * (1.0 - c)
        return np.where(c > zero, 2.0 * m * c - n * w, 0.0)  # D / w

    return slope, [zero]


_SLOPES: dict[str, Callable[[int], tuple[Slope, list[float]]]] = {
    "quadratic": _quadratic_slope,
    "cubic": _cubic_slope,
    "piecewise": _piecewise_slope,
    "log2": _log2_slope,
    "cosine_quadratic": _cosine_quadratic_slope,
}
"""Per form: (a function with the sign of the relative error's derivative in c, or of its
negative, 0 where the form is clipped to 0; the cuts between which it is monotone)."""


def _bisect(f: Callable[[float], float], lo: float, hi: float) -> tuple[float, float]:
    """Adjacent floats (or one float twice) around a sign change of f on [lo, hi]."""
    f_lo = f(lo)
    while True:
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            return lo, hi
        f_mid = f(mid)
        if f_mid == 0.0:
            return mid, mid
        if (f_mid > 0.0) == (f_lo > 0.0):
            lo, f_lo = mid, f_mid
        else:
            hi = mid


def max_rel_error(form: str, n: int, level: float | None = None) -> Peak:
    """Max |approx / cos^n d - 1| of ``form`` over the epicentre d in [0, arctan(1/sqrt(n-1))]
    (or, with ``level``, over d in [0, arccos(level^(1/n))], where cos^n d >= level), exactly.

    Why the candidates are all (in c = cos d, which the map d -> c turns round monotonically):
    e(c) = A(c) / c^n - 1 has e'(c) = c^(-n-1) D(c) with D = c A' - n A, so the maximum of |e|
    lies at an end of the range, at a cut (a kink of A), or at a root of D.  Per form, D has
    the sign of a function that is monotone between the cuts, so each piece holds at most one
    root, found by bisection to adjacent floats (the pieces are further cut into ``GRID``
    cells, which changes nothing where the argument holds and guards where it would not):
    * quadratic, A = c w, w = 1 - a (1 - c): D = c ((1-n) w + a c), linear in c; cut where
      w = 0;
    * cubic, A = c P(c), P = p0 + p1 t + a1 t^2 about t = c - s: D = c ((1-n) P + c P')
      = c t (C1 + C2 t) with C2 = (3-n) a1, C1 = (2-n) p1 + 2 a1 s (no constant term: the
      tangency at s is a root), a quadratic in c: cut at its vertex, and where P = 0;
    * piecewise: the cubic's D for c > s = 0.5^(1/n), and for the bloom part
      A = c / (alpha - beta c): D = c (alpha (1-n) + n beta c) / (alpha - beta c)^2, whose
      numerator is 2 n (n-1) (c - s), linear (its one root is s itself); cut at s;
    * log2, with u = 1 - n log2 c (decreasing in c): de/du has the sign of
      g(u) = ln2 u - u ln(u) / 2 - 1 / (2 ln2), concave (g'' = -1/(2u)): cut at its maximum
      u = 4/e, and at u = 4 (beyond it A = 0);
    * cosine-quadratic, A = w^2, w = 1 - m (1 - c): D = w (2 m c - n w), for w > 0 linear in
      c; cut at w = 0 (below it A = 0, e = -1).
    The roots' positions carry the rounding of these sign functions, but the error is
    stationary there, so its value at the bracketing floats is the maximum to float precision.
    Where A is clipped to 0, e = -1 is constant, and the cut gives it.
    """
    _check_form(form)
    n = check_n(n)
    if level is not None and not 0.0 < level < 1.0:
        raise ValueError(f"level = {level!r} is out of range: legal is 0 < level < 1")
    return _max_rel_error(form, n, level)


@functools.cache
def _max_rel_error(form: str, n: int, level: float | None) -> Peak:
    d_end = epicentre(n) if level is None else math.acos(level ** (1.0 / n))
    lo = math.cos(d_end)
    slope, cuts = _SLOPES[form](n)
    knots = sorted({lo, 1.0, *(float(x) for x in cuts if lo < x < 1.0)})
    candidates = list(knots)

    def scalar(c: float) -> float:
        return float(slope(np.float64(c)))

    for a, b in itertools.pairwise(knots):
        grid = np.linspace(a, b, GRID + 1)
        signs = np.sign(slope(grid))
        candidates += [float(x) for x in grid[signs == 0.0]]
        for i in np.flatnonzero(signs[:-1] * signs[1:] < 0.0):
            candidates += _bisect(scalar, float(grid[i]), float(grid[i + 1]))
    cs = np.array(candidates)
    errs = np.abs(_OF_COS[form](cs, n) / cs**n - 1.0)
    best = int(np.argmax(errs))
    return Peak(float(errs[best]), math.acos(min(1.0, float(cs[best]))))


def worst_errors(form: str, level: float | None = None) -> np.ndarray:
    """``max_rel_error(form, n, level).error`` for n = 1..N_MAX (index n - 1)."""
    return np.array([max_rel_error(form, n, level).error for n in range(1, N_MAX + 1)])
