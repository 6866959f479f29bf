# SPDX-License-Identifier: Apache-2.0
"""Specular unit: the float approximation cos^k(a d) of cos^n d and its exact worst errors.

Owns ``brdf_approx`` and the certified maxima of its relative error in the highlight's epicentre
(``brdf_max_rel_error``, found exactly from the one root of the error's derivative) and of its
absolute error over [0, pi] (``brdf_max_abs_error``, branch and bound to ``ABS_ERROR_TOL``),
with ``cos_power_max_slope``.  No fixed-point arithmetic here: it measures the patent's idea,
not the unit.  May import numpy, numba, ``model.units.fixed`` and ``config``.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numba import njit

from model.units import fixed
from model.units.specular.config import N_MAX, alpha_value, epicentre


def brdf_approx(delta: np.ndarray, n: int, k: int, alpha: str = "taylor") -> np.ndarray:
    """cos^k(a*delta), 0 once a*delta reaches pi/2 (float, delta in radians, >= 0)."""
    x = alpha_value(n, k, alpha) * np.abs(np.asarray(delta, dtype=np.float64))
    return np.cos(np.minimum(x, np.pi / 2)) ** k  # cos(pi/2) is 6e-17 in float, like cos^n


def _check_n_k(n: int, k: int) -> None:
    fixed.check_operand("n", n, 1, N_MAX)
    fixed.check_operand("k", k, 1, 64)


def brdf_max_rel_error(n: int, k: int, alpha: str = "taylor", floor: float = 0.0) -> float:
    """Max |cos^k(a d) - cos^n d| / cos^n d over the epicentre d in [0, arctan(1/sqrt(n-1))],
    exactly (not sampled), where also cos^n d >= ``floor`` (0: the whole epicentre; for n = 1
    it ends at the float pi/2, where cos is 6e-17, not 0).

    Why the maximum is one of at most three points (``_rel_error_max``): with r(d) =
    cos^k(a d) / cos^n d, (log r)' = n tan d - k a tan(a d) = tan d * (n - k a h(d)) with
    h(d) = tan(a d) / tan d.  For a > 1, h is strictly increasing on (0, pi/(2a)) (its log
    derivative 2a / sin(2ad) - 2 / sin(2d) > 0 because sin(x)/x decreases on (0, pi]); for
    a < 1 strictly decreasing; for a = 1 constant.  So (log r)' changes sign at most once: r is
    unimodal, and |r - 1| is largest at d = 0 (0), at the end of the range, or at the one root
    of n = k a h(d) (found by bisection to the last float).  Once a d >= pi/2 the approximation
    is 0 and the error 1, which the end point gives.  For a = sqrt(n/k) there is no root at all
    (h starts at a and moves away from n / (k a) = a): the error grows monotonically to the end.
    """
    _check_n_k(n, k)
    return _brdf_max_rel_error(int(n), int(k), alpha, float(floor))


@functools.cache
def _brdf_max_rel_error(n: int, k: int, alpha: str, floor: float) -> float:
    d_end = epicentre(n)
    if floor > 0:
        d_end = min(d_end, math.acos(floor ** (1.0 / n)))
    return float(_rel_error_max(n, k, alpha_value(n, k, alpha), d_end))


@njit(cache=True)
def _rel_error_at(d: float, n: int, k: int, a: float) -> float:
    return abs(np.cos(min(a * d, np.pi / 2)) ** k / np.cos(d) ** n - 1.0)


@njit(cache=True)
def _rel_error_max(n: int, k: int, a: float, d_end: float) -> float:
    """max over d in [0, d_end] of |cos^k(min(a d, pi/2)) / cos^n d - 1| (``brdf_max_rel_error``
    says why the end point and the one root of n - k a tan(a d) / tan(d) are enough)."""
    best = _rel_error_at(d_end, n, k, a)
    s0 = n - k * a * a  # n - k a h(d) as d -> 0
    clipped = a * d_end >= np.pi / 2  # the approximation reaches 0 inside the range
    s1 = -np.inf if clipped else n - k * a * np.tan(a * d_end) / np.tan(d_end)
    if s0 == 0.0 or s1 == 0.0 or (s0 > 0.0) == (s1 > 0.0):
        return best
    lo, hi = 0.0, min(d_end, np.pi / (2 * a))
    while True:  # bisection down to adjacent floats
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if (n - k * a * np.tan(a * mid) / np.tan(mid) > 0.0) == (s0 > 0.0):
            lo = mid
        else:
            hi = mid
    return max(best, _rel_error_at(lo, n, k, a), _rel_error_at(hi, n, k, a))


ABS_ERROR_TOL = 1e-9
"""``brdf_max_abs_error`` is certified to lie at most this much (full scale 1) above the true
maximum, never below it."""


def brdf_max_abs_error(n: int, k: int, alpha: str = "taylor") -> float:
    """Max |cos^k(a d) - max(0, cos d)^n| over d in [0, pi] (full scale = 1): an upper bound at
    most ``ABS_ERROR_TOL`` above the true maximum, by branch and bound (``_abs_error_max``).

    The error e is piecewise C^1 with a Lipschitz derivative: |(cos^m)''| =
    |m(m-1) cos^(m-2) sin^2 - m cos^m| <= max(2(m-1), m) <= 2m (cos^(m-2) sin^2 <= 2/m), so
    |e''| <= M = 2 k a^2 + 2 n away from the kinks (a d = pi/2 for k = 1, d = pi/2 for n = 1,
    where the grid is cut).  On a cell [x0, x1] of width h, |e| <= max(|e(x0)|, |e(x1)|) +
    M h^2 / 8; cells are split until that bound is within the tolerance of the best value
    seen.  For n = k the two sides are the same function but for the rounding of a:
    |e| <= S_k |a - 1| pi, S_k the largest slope of cos^k (``cos_power_max_slope``).
    """
    _check_n_k(n, k)
    return _brdf_max_abs_error(int(n), int(k), alpha)


@functools.cache
def _brdf_max_abs_error(n: int, k: int, alpha: str) -> float:
    a = alpha_value(n, k, alpha)
    if n == k:
        return cos_power_max_slope(k) * abs(a - 1.0) * math.pi
    return float(_abs_error_max(n, k, a, ABS_ERROR_TOL, 256))


def cos_power_max_slope(k: int) -> float:
    """max over x of |d/dx cos^k x| = sqrt(k) ((k-1)/k)^((k-1)/2), at tan^2 x = 1/(k-1)."""
    return 1.0 if k == 1 else math.sqrt(k) * ((k - 1) / k) ** ((k - 1) / 2)


@njit(cache=True)
def _abs_error_at(d: float, n: int, k: int, a: float) -> float:
    return abs(np.cos(min(a * d, np.pi / 2)) ** k - max(np.cos(d), 0.0) ** n)


@njit(cache=True)
def _abs_error_max(n: int, k: int, a: float, tol: float, grid: int) -> float:
    """Branch and bound for ``brdf_max_abs_error``: returns an upper bound within tol of the
    maximum (depth first; every discarded cell's bound is kept in the result)."""
    m2 = 2.0 * k * a * a + 2.0 * n
    cuts = [0.0, np.pi]
    if k == 1 and a > 0.5:
        cuts.append(np.pi / (2 * a))
    if n == 1:
        cuts.append(np.pi / 2)
    cuts.sort()
    cap = 1 << 14
    x0s, x1s = np.empty(cap), np.empty(cap)
    e0s, e1s = np.empty(cap), np.empty(cap)
    best = _abs_error_at(0.0, n, k, a)
    top = 0
    for p in range(len(cuts) - 1):
        lo, hi = cuts[p], cuts[p + 1]
        if hi <= lo:
            continue
        x_prev, e_prev = lo, _abs_error_at(lo, n, k, a)
        for g in range(1, grid + 1):
            x = hi if g == grid else lo + (hi - lo) * g / grid
            e = _abs_error_at(x, n, k, a)
            best = max(best, e)
            x0s[top], x1s[top], e0s[top], e1s[top] = x_prev, x, e_prev, e
            top += 1
            x_prev, e_prev = x, e
    bound = best
    while top > 0:
        top -= 1
        x0, x1, e0, e1 = x0s[top], x1s[top], e0s[top], e1s[top]
        cell = max(e0, e1) + m2 * (x1 - x0) ** 2 / 8.0
        xm = 0.5 * (x0 + x1)
        if cell <= best + tol or xm <= x0 or xm >= x1:
            bound = max(bound, cell)
            continue
        if top + 2 > cap:
            raise RuntimeError("branch and bound stack overflow")
        em = _abs_error_at(xm, n, k, a)
        best = max(best, em)
        x0s[top], x1s[top], e0s[top], e1s[top] = x0, xm, e0, em
        x0s[top + 1], x1s[top + 1], e0s[top + 1], e1s[top + 1] = xm, x1, em, e1
        top += 2
    return max(bound, best)
