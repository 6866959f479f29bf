"""Specular unit of patent UA 71489 (SEEDS.md section 1): ``I = C * cos^k(a * zeta)`` per pixel.

Blinn's highlight ``cos^n(delta)`` along a scan line becomes, after the float set-up of the
"external device" (``setup_line``), ``C * cos^n(zeta)`` with an angle ``zeta`` that grows by a
constant ``dz`` per pixel.  The unit approximates ``cos^n(x) ~ cos^k(a * x)`` with one of a few
tables of ``cos^k`` (k chosen by a decoder from n) and a per-n scale ``a`` (ROM 9), so it needs
no power function: per pixel an add, a multiply, a table read and a multiply (fig. 1).

Formats (``SpecularConfig``, every value an integer in units of 2**-f):
* angles ``dz``, ``z0`` and the accumulator (register 8) in units of pi/2, two's complement,
  ``z_frac_bits`` fraction bits; ``dz``/``z0`` are ``z_int_bits + z_frac_bits`` wide, the
  accumulator ``len_width`` bits wider, so ``z0 + l*dz`` cannot wrap for any register values;
* ``a`` (ROM 9, one word per n = 0..1023): unsigned Q``a_int_bits``.``a_frac_bits``, 0 for
  invalid n;
* the scaled angle ``|zeta| * a`` (multiplier 11) is rounded to ``rom_addr_bits`` fraction bits:
  that is the ROM-12 address inside the table of the decoded k; a value that rounds to 1 (pi/2)
  or more gives cos^k = 0 (overflow detected, never wrapped);
* ROM 12 words: ``round(cos^k(i/2**A * pi/2) * 2**D)``, saturated to ``2**D - 1`` (i = 0 would
  be exactly 2**D); D = ``rom_data_bits``;
* ``C``: unsigned Q``c_int_bits``.``c_frac_bits`` in output LSBs; the output is
  ``saturate(round(C * rom12 / 2**(c_frac_bits + D)), 0, 2**out_width - 1)``.

Named steps, in the order the RTL takes them: accumulate (exact), magnitude and saturation of
``|zeta|`` to ``mag_int_bits`` integer bits (invisible: every clamped value already gives 0),
multiply by a (exact), round to the address (add half, slice), overflow -> 0, table read,
multiply by C (exact), round (add half, slice), saturate.

Timing (``cycles``): a line of l intervals keeps ``busy`` high for ``FILL_LATENCY + l`` cycles;
the l + 1 results come one per clock at offsets ``FILL_LATENCY .. FILL_LATENCY + l`` after the
start edge, the last one together with busy = 0.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numba import njit

from model.units import fixed, rom

N_WIDTH = 10
"""Width of the n register and of the decoder: n = 1..1000 needs 10 bits (the patent says 9)."""
N_MAX = 1000
FILL_LATENCY = 5
"""Clock edges from an accepted start to the first valid: acc, |acc|, x a, ROM 12, x C, round."""
MAX_TABLES = 4
ALPHA_MODES = ("taylor", "inflection")

PATENT_K_RANGES = ((1, 1, 1), (2, 2, 2), (3, 6, 4), (7, 1000, 16))
"""The patent's mapping (fig. 13): (n_lo, n_hi, k) -> k = 1, 2, 4, 16."""
PROTOTYPE_K_RANGES = ((1, 1000, 2),)
"""The prototype (Abbas, Szirmay-Kalos, Horvath 2000): cos^2 only, a = sqrt(n/2)."""


# ==================================================================== float: the approximation
def epicentre(n: int) -> float:
    """Inflection point of cos^n: arctan(1/sqrt(n-1)) rad (pi/2 for n = 1)."""
    return math.pi / 2 if n == 1 else math.atan(1.0 / math.sqrt(n - 1))


def alpha_value(n: int, k: int, alpha: str = "taylor") -> float:
    """The scale a of ``cos^n(d) ~ cos^k(a*d)`` (float).

    ``"taylor"``: a = sqrt(n/k) (equal second Maclaurin terms, the patent).
    ``"inflection"``: a = arccos(((n-1)/n)^(n/(2k))) / arctan(1/sqrt(n-1)) (the thesis: exact at
    the inflection point of cos^n); for n = 1 the limit is 1 (pi/2 / pi/2).
    """
    if alpha == "taylor":
        return math.sqrt(n / k)
    if alpha == "inflection":
        if n == 1:
            return 1.0
        return math.acos(((n - 1) / n) ** (n / (2 * k))) / epicentre(n)
    raise ValueError(f"alpha = {alpha!r} is out of range: legal modes are {ALPHA_MODES}")


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


def _n_k_pairs(ranges) -> list[tuple[int, int]]:
    return [(n, k) for lo, hi, k in ranges for n in range(lo, hi + 1)]


def _rom9_words(cfg: SpecularConfig) -> np.ndarray:
    words = np.zeros(1 << N_WIDTH, dtype=np.int64)
    for n, k in _n_k_pairs(cfg.k_ranges):
        words[n] = math.floor(alpha_value(n, k, cfg.alpha) * 2**cfg.a_frac_bits + 0.5)
    return words


@dataclass(frozen=True)
class SpecularConfig:
    """Formats and table choices of the specular unit (defaults: the patent's unit, 8-bit out).

    Why these defaults:
    * ``rom_addr_bits`` = 12: the address half-step is pi/2 * 2**-13 = 1.9e-4 rad of the scaled
      angle; at the edge of the highlight epicentre cos^16 has a relative slope of about 4/rad,
      so the table adds at most 0.083 % (n >= 2, ``make accuracy``) to the approximation's own
      <= 1.0895 %;
    * ``z_frac_bits`` = 26: with dz and z0 rounded to 2**-27, the accumulated angle after
      l <= 2047 intervals is within 2048 * 2**-27 = 2**-16 (units of pi/2) of the exact
      z0 + t*gamma; times the largest a (sqrt(1000/16) = 7.9) that is 1.2e-4, half a ROM-12
      address step (2**-12);
    * ``a_frac_bits`` = 14: a relative error of a below 2**-15 / 0.66 = 5e-5;
    * ``rom_data_bits`` = 16: table values to 1.5e-5, far below an 8-bit output LSB;
    * C: Q8.8, so C up to 255.996 output LSBs with 1/256 resolution.
    """

    c_int_bits: int = 8  # C register: unsigned integer bits (output LSBs)
    c_frac_bits: int = 8  # C register: fraction bits
    z_int_bits: int = 3  # dz, z0: integer bits incl. sign (units of pi/2): [-4, 4)
    z_frac_bits: int = 26  # dz, z0 and accumulator fraction bits
    len_width: int = 11  # interval counter: l = 0..2047
    a_int_bits: int = 3  # ROM 9 word integer bits (a <= sqrt(1000/16) = 7.9)
    a_frac_bits: int = 14  # ROM 9 word fraction bits
    rom_addr_bits: int = 12  # ROM 12 address bits per table (fraction bits of the scaled angle)
    rom_data_bits: int = 16  # ROM 12 word bits
    out_width: int = 8  # output intensity bits
    k_ranges: tuple[tuple[int, int, int], ...] = field(default=PATENT_K_RANGES)
    alpha: str = "taylor"  # "taylor": a = sqrt(n/k); "inflection": exact at the inflection point

    def __post_init__(self) -> None:
        fixed.check_width("c_int_bits", self.c_int_bits, 1, 16)
        fixed.check_width("c_frac_bits", self.c_frac_bits, 0, 16)
        fixed.check_width("z_int_bits", self.z_int_bits, 3, 8)
        fixed.check_width("z_frac_bits", self.z_frac_bits, 1, 40)
        fixed.check_width("len_width", self.len_width, 1, 16)
        fixed.check_width("a_int_bits", self.a_int_bits, 1, 8)
        fixed.check_width("a_frac_bits", self.a_frac_bits, 1, 24)
        fixed.check_width("rom_addr_bits", self.rom_addr_bits, 2, 16)
        fixed.check_width("rom_data_bits", self.rom_data_bits, 2, 24)
        fixed.check_width("out_width", self.out_width, 1, 16)
        # JSON (the bench's BENCH_CONFIG) turns the tuples into lists: normalise back.
        ranges = tuple(tuple(int(v) for v in r) for r in self.k_ranges)
        object.__setattr__(self, "k_ranges", ranges)
        _check_k_ranges(ranges)
        if self.alpha not in ALPHA_MODES:
            raise ValueError(
                f"alpha = {self.alpha!r} is out of range: legal modes are {ALPHA_MODES}"
            )
        if self.addr_shift < 1:
            raise ValueError(
                f"z_frac_bits + a_frac_bits = {self.z_frac_bits + self.a_frac_bits} is out of "
                f"range: it must exceed rom_addr_bits = {self.rom_addr_bits}"
            )
        for name, width in (
            ("accumulator width z_int_bits + z_frac_bits + len_width", self.acc_width),
            ("product width", self.mag_width + self.a_width + 1),
            ("c_int_bits + c_frac_bits + rom_data_bits", self.c_width + self.rom_data_bits + 1),
        ):
            if width > fixed.MAX_KERNEL_WIDTH:
                raise ValueError(
                    f"{name} = {width} is out of range: at most {fixed.MAX_KERNEL_WIDTH} bits"
                )
        a_max = max(alpha_value(n, k, self.alpha) for n, k in _n_k_pairs(ranges))
        if round(a_max * 2**self.a_frac_bits) >= 1 << self.a_width:
            raise ValueError(_a_width_message(a_max, self.a_int_bits, self.a_frac_bits))

    # ---------------------------------------------------------------- derived widths
    @property
    def c_width(self) -> int:
        return self.c_int_bits + self.c_frac_bits

    @property
    def c_format(self) -> fixed.QFormat:
        return fixed.QFormat(self.c_int_bits, self.c_frac_bits, signed=False)

    @property
    def z_width(self) -> int:
        return self.z_int_bits + self.z_frac_bits

    @property
    def z_format(self) -> fixed.QFormat:
        return fixed.QFormat(self.z_int_bits, self.z_frac_bits, signed=True)

    @property
    def acc_width(self) -> int:
        """Register 8: |z0| + l*|dz| <= 2**(z_int_bits-1) * 2**len_width fits, signed."""
        return self.z_width + self.len_width

    @property
    def a_width(self) -> int:
        return self.a_int_bits + self.a_frac_bits

    @property
    def len_max(self) -> int:
        return (1 << self.len_width) - 1

    @property
    def out_max(self) -> int:
        return (1 << self.out_width) - 1

    @property
    def num_tables(self) -> int:
        return len(self.k_ranges)

    @property
    def rom9_bits(self) -> int:
        """ROM 9: one a word for every 10-bit n."""
        return (1 << N_WIDTH) * self.a_width

    @property
    def rom12_bits(self) -> int:
        """ROM 12: one cos^k table of 2**rom_addr_bits words per k in the set."""
        return self.num_tables * (1 << self.rom_addr_bits) * self.rom_data_bits

    @property
    def rom_bits(self) -> int:
        return self.rom9_bits + self.rom12_bits

    @property
    def tsel_bits(self) -> int:
        """High ROM-12 address bits (table select); at least 1 so the RTL never has 0 bits."""
        return max(1, (self.num_tables - 1).bit_length())

    @property
    def ks(self) -> tuple[int, ...]:
        return tuple(r[2] for r in self.k_ranges)

    @property
    def n_hi(self) -> tuple[int, ...]:
        return tuple(r[1] for r in self.k_ranges)

    @property
    def addr_shift(self) -> int:
        """Bits dropped from the product |zeta| * a to form the ROM-12 address."""
        return self.z_frac_bits + self.a_frac_bits - self.rom_addr_bits

    @property
    def mag_int_bits(self) -> int:
        """Integer bits |zeta| is saturated to before multiplier 11.

        The smallest M such that the clamped value times the smallest a of any valid n still
        reaches pi/2 (cos^k = 0): clamping then never changes a result, it only narrows the
        multiplier.  Capped at the accumulator's own integer bits.
        """
        return _mag_int_bits(self)

    @property
    def mag_width(self) -> int:
        return self.mag_int_bits + self.z_frac_bits

    @property
    def rom_tag(self) -> str:
        return "_".join(
            f"n{lo}-{hi}k{k}" if lo != hi else f"n{lo}k{k}" for lo, hi, k in self.k_ranges
        )

    @property
    def rom_ks(self) -> tuple[int, int, int, int]:
        """k of each of the four decoder outputs, 0 for an unused one (RTL K0..K3)."""
        return (*self.ks, *(0,) * (MAX_TABLES - self.num_tables))

    @property
    def a_rom_name(self) -> str:
        return f"specular_a_{self.alpha}_{self.rom_tag}_q{self.a_int_bits}.{self.a_frac_bits}.hex"

    @property
    def cos_rom_name(self) -> str:
        kset = "-".join(str(k) for k in self.ks)
        return f"specular_cos_k{kset}_a{self.rom_addr_bits}_d{self.rom_data_bits}.hex"

    def hdl_parameters(self) -> dict[str, object]:
        """The Verilog parameters of ``rtl/specular_unit.v`` for this configuration."""
        hi = list(self.n_hi) + [N_MAX] * (MAX_TABLES - self.num_tables)
        ks = self.rom_ks
        return {
            "C_INT_BITS": self.c_int_bits,
            "C_FRAC_BITS": self.c_frac_bits,
            "Z_INT_BITS": self.z_int_bits,
            "Z_FRAC_BITS": self.z_frac_bits,
            "LEN_WIDTH": self.len_width,
            "A_INT_BITS": self.a_int_bits,
            "A_FRAC_BITS": self.a_frac_bits,
            "ROM_ADDR_BITS": self.rom_addr_bits,
            "ROM_DATA_BITS": self.rom_data_bits,
            "OUT_WIDTH": self.out_width,
            "NUM_TABLES": self.num_tables,
            "N_HI0": hi[0],
            "N_HI1": hi[1],
            "N_HI2": hi[2],
            "N_HI3": hi[3],
            "K0": ks[0],
            "K1": ks[1],
            "K2": ks[2],
            "K3": ks[3],
            "ALPHA": self.alpha,
            "MAG_INT_BITS": self.mag_int_bits,
            "A_ROM_FILE": str(rom_path(self, "a")),
            "COS_ROM_FILE": str(rom_path(self, "cos")),
        }


def _check_k_ranges(ranges: tuple[tuple[int, int, int], ...]) -> None:
    if not 1 <= len(ranges) <= MAX_TABLES:
        raise ValueError(
            f"k_ranges has {len(ranges)} entries: out of range, legal is 1..{MAX_TABLES} "
            "(the decoder has four outputs)"
        )
    expect_lo = 1
    for r in ranges:
        if len(r) != 3:
            raise ValueError(f"k_ranges entry {r!r} must be (n_lo, n_hi, k)")
        lo, hi, k = r
        if lo != expect_lo or hi < lo:
            raise ValueError(
                f"k_ranges entry {r!r} is out of range: ranges must cover n = 1..{N_MAX} in "
                f"order without gaps (expected n_lo = {expect_lo}, n_hi >= n_lo)"
            )
        if not 1 <= k <= 64:
            raise ValueError(f"k = {k} is out of range: legal range is 1..64")
        expect_lo = hi + 1
    if expect_lo != N_MAX + 1:
        raise ValueError(
            f"k_ranges end at n = {expect_lo - 1}: out of range, they must end at n = {N_MAX}"
        )


def _a_width_message(a_max: float, int_bits: int, frac_bits: int) -> str:
    """Why ROM 9's Q``int_bits``.``frac_bits`` cannot hold the largest a, and what would.

    The word is a rounded to ``frac_bits`` fraction bits, so a = 7.9057 needs 4 integer bits at
    1 fraction bit (it rounds to 8) but 3 at 14: the message names both fields."""
    word = round(a_max * 2**frac_bits)
    need = word.bit_length() - frac_bits
    frac_ok = next(
        (f for f in range(frac_bits + 1, 25) if round(a_max * 2**f) < 1 << (int_bits + f)), None
    )
    legal = f"a_int_bits >= {need} with a_frac_bits = {frac_bits}"
    if frac_ok is not None:
        legal += f", or a_frac_bits >= {frac_ok} with a_int_bits = {int_bits}"
    why = f"the largest a = {a_max:.4f} needs {need} integer bits"
    if need > math.floor(math.log2(a_max)) + 1:
        why = (
            f"the largest a = {a_max:.4f} rounds to {word / 2**frac_bits:g} at "
            f"a_frac_bits = {frac_bits} (the ROM 9 word), which needs {need} integer bits"
        )
    return f"a_int_bits = {int_bits} is out of range: {why}: legal is {legal}"


@functools.cache
def _mag_int_bits(cfg: SpecularConfig) -> int:
    a_min = int(_rom9_words(cfg)[1 : N_MAX + 1].min())
    one = 1 << (cfg.z_frac_bits + cfg.a_frac_bits)
    cap = cfg.z_int_bits + cfg.len_width - 1
    m = 0
    while m < cap and a_min * ((1 << (m + cfg.z_frac_bits)) - 1) < one:
        m += 1
    return m


DEFAULT = SpecularConfig()
PROTOTYPE = SpecularConfig(k_ranges=PROTOTYPE_K_RANGES, a_int_bits=5)
"""The prototype the patent improves on: one cos^2 table, a = sqrt(n/2) (up to 22.4)."""
INFLECTION = SpecularConfig(alpha="inflection")
"""The patent's four tables with the thesis's a (exact at the inflection point)."""
NARROW = SpecularConfig(
    c_int_bits=6,
    c_frac_bits=4,
    z_frac_bits=18,
    len_width=7,
    a_frac_bits=10,
    rom_addr_bits=8,
    rom_data_bits=10,
    out_width=6,
)
"""A narrow unit (lines up to 127 intervals, 6-bit output, 256-entry tables) for the benches."""

# Configurations whose ROM images are committed under rtl/rom (``make roms``); the benches use them.
ROM_CONFIGS: dict[str, SpecularConfig] = {
    "default": DEFAULT,
    "narrow": NARROW,
    "prototype": PROTOTYPE,
    "inflection": INFLECTION,
}


# ==================================================================== decoder and ROMs
def _table_index(n: np.ndarray, cfg: SpecularConfig) -> np.ndarray:
    """Index of the k range holding each n (0 for n outside 1..1000, flagged by n_err)."""
    idx = np.zeros(np.shape(n), dtype=np.int64)
    for j, (lo, hi, _) in enumerate(cfg.k_ranges):
        idx = np.where((n >= lo) & (n <= hi), j, idx)
    return idx


def decode_k(n, cfg: SpecularConfig = DEFAULT):
    """The decoder (block 10): k of the cos^k table used for n = 1..1000 (10-bit n).

    The patent's decoder has 9 inputs n1..n9 "because n = 1..1000", but 1000 needs 10 bits: a
    9-bit decoder sees n mod 512 and aliases every n >= 512 (see ``decode_k_patent9``).  This
    unit decodes all 10 bits.
    """
    n_arr = fixed.check_operand("n", n, 1, N_MAX)
    k = np.asarray(cfg.ks, dtype=np.int64)[_table_index(n_arr, cfg)]
    return int(k) if k.ndim == 0 else k


def decode_k_patent9(n, cfg: SpecularConfig = DEFAULT):
    """What the patent's 9-input decoder would give for a 10-bit n: k of (n mod 512), 0 = none.

    For n >= 512 it answers for n - 512: n = 513 gets the cos table (k = 1) instead of cos^16,
    and n = 512 gets no table at all.
    """
    n_arr = fixed.check_operand("n", n, 0, (1 << N_WIDTH) - 1) & 511
    k = np.where(n_arr >= 1, np.asarray(cfg.ks, dtype=np.int64)[_table_index(n_arr, cfg)], 0)
    return int(k) if k.ndim == 0 else k


def n_valid(n: int) -> bool:
    """Whether the unit accepts n (1..1000); otherwise it outputs 0 with n_err = 1."""
    return 1 <= n <= N_MAX


def rom9_words(cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """ROM 9: a = round(alpha_value(n, k) * 2**a_frac_bits) for n = 0..1023; 0 for invalid n."""
    return _rom9_words(cfg)


def cos_table(k: int, addr_bits: int, data_bits: int) -> np.ndarray:
    """One ROM-12 table: round(cos^k(i/2**A * pi/2) * 2**D) saturated to 2**D - 1, i < 2**A."""
    x = np.arange(1 << addr_bits, dtype=np.float64) * (np.pi / 2) / 2**addr_bits
    words = np.floor(np.cos(x) ** k * 2.0**data_bits + 0.5).astype(np.int64)
    return np.minimum(words, (1 << data_bits) - 1)


def rom12_words(cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """ROM 12: the tables of cfg.ks one after the other (address = {table, angle}), 0-padded
    to 2**tsel_bits tables."""
    size = 1 << cfg.rom_addr_bits
    words = np.zeros(size << cfg.tsel_bits, dtype=np.int64)
    for j, k in enumerate(cfg.ks):
        words[j * size : (j + 1) * size] = cos_table(k, cfg.rom_addr_bits, cfg.rom_data_bits)
    return words


def rom_layout(cfg: SpecularConfig = DEFAULT, which: str = "a") -> rom.RomLayout:
    """The image of ROM 9 (``which="a"``) or ROM 12 (``"cos"``) and the RTL parameters its
    contents depend on (``rom.KIND_FIELDS``)."""
    ks = tuple(zip(("K0", "K1", "K2", "K3"), cfg.rom_ks, strict=True))
    if which == "a":
        hi = (*cfg.n_hi, *(N_MAX,) * (MAX_TABLES - cfg.num_tables))
        config = (
            ("A_INT_BITS", cfg.a_int_bits),
            ("A_FRAC_BITS", cfg.a_frac_bits),
            ("ALPHA", rom.ALPHA_NAMES.index(cfg.alpha)),
            ("NUM_TABLES", cfg.num_tables),
            *zip(("N_HI0", "N_HI1", "N_HI2", "N_HI3"), hi, strict=True),
            *ks,
        )
        return rom.RomLayout("specular_a", 1 << N_WIDTH, cfg.a_width, config)
    if which == "cos":
        config = (
            ("ROM_ADDR_BITS", cfg.rom_addr_bits),
            ("ROM_DATA_BITS", cfg.rom_data_bits),
            ("NUM_TABLES", cfg.num_tables),
            *ks,
        )
        depth = 1 << (cfg.tsel_bits + cfg.rom_addr_bits)
        return rom.RomLayout("specular_cos", depth, cfg.rom_data_bits, config)
    raise ValueError(f"which = {which!r} is out of range: legal are 'a', 'cos'")


def read_rom(cfg: SpecularConfig = DEFAULT, which: str = "a", path=None) -> list[int]:
    """The data words of the image at ``path`` (default ``rom_path(cfg, which)``), checked
    against ``cfg`` (``rom.read_hex``: a bad or foreign image raises ``rom.RomFileError``)."""
    return rom.read_hex(rom_path(cfg, which) if path is None else path, rom_layout(cfg, which))


def rom_text(cfg: SpecularConfig = DEFAULT, which: str = "a") -> str:
    """The ``$readmemh`` image of ROM 9 (``which="a"``) or ROM 12 (``which="cos"``)."""
    ranges = ", ".join(f"{lo}..{hi} -> k = {k}" for lo, hi, k in cfg.k_ranges)
    if which == "a":
        header = (
            f"specular_unit ROM 9: a(n) for n = 0..{(1 << N_WIDTH) - 1} ({cfg.alpha}), "
            f"unsigned Q{cfg.a_int_bits}.{cfg.a_frac_bits}\n"
            f"k ranges: {ranges}; invalid n (0, >{N_MAX}) hold 0. Generated by model.specular."
        )
        return rom.format_image(rom9_words(cfg), rom_layout(cfg, "a"), header)
    if which == "cos":
        header = (
            f"specular_unit ROM 12: cos^k(i/2^{cfg.rom_addr_bits} * pi/2) * 2^{cfg.rom_data_bits}"
            f" (saturated), tables k = {', '.join(map(str, cfg.ks))}\n"
            f"address = {{table ({cfg.tsel_bits} bits), i ({cfg.rom_addr_bits} bits)}}; "
            "unused tables hold 0. Generated by model.specular."
        )
        return rom.format_image(rom12_words(cfg), rom_layout(cfg, "cos"), header)
    raise ValueError(f"which = {which!r} is out of range: legal are 'a', 'cos'")


def rom_path(cfg: SpecularConfig = DEFAULT, which: str = "a") -> Path:
    if which not in ("a", "cos"):
        raise ValueError(f"which = {which!r} is out of range: legal are 'a', 'cos'")
    return rom.ROM_DIR / (cfg.a_rom_name if which == "a" else cfg.cos_rom_name)


def write_roms() -> list[Path]:
    """Write ROM 9 and ROM 12 of every configuration in ``ROM_CONFIGS`` to rtl/rom/."""
    paths = []
    for cfg in ROM_CONFIGS.values():
        for which in ("a", "cos"):
            path = rom_path(cfg, which)
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(rom_text(cfg, which))
            paths.append(path)
    return list(dict.fromkeys(paths))


# ==================================================================== the bit-exact datapath
@njit(cache=True)
def _accumulate(dz: int, z0: int, length: int, acc: np.ndarray) -> None:
    """Adder 6 + multiplexer 7 + register 8: acc[0] = z0, acc[i] = acc[i-1] + dz (exact)."""
    value = z0
    for i in range(length + 1):
        if i > 0:
            value += dz
        acc[i] = value


@njit(cache=True)
def _rom12_word(
    acc: int, a_word: int, tsel: int, rom12: np.ndarray, mag_max: int, shift: int, addr_bits: int
) -> int:
    """|acc| (saturated), x a (multiplier 11), rounded to the address, ROM 12; 0 from pi/2 on."""
    mag = fixed.saturate(abs(acc), 0, mag_max)
    prod = mag * a_word
    addr = fixed.round_shift(prod, shift)
    if addr >= (1 << addr_bits):
        return 0
    return rom12[(tsel << addr_bits) | addr]


@njit(cache=True)
def _pixels(
    acc: np.ndarray,
    c: int,
    a_word: int,
    tsel: int,
    rom12: np.ndarray,
    mag_max: int,
    shift: int,
    addr_bits: int,
    out_shift: int,
    out_max: int,
    out: np.ndarray,
) -> None:
    """Per pixel: the ROM-12 word, x C (multiplier 13), round, saturate."""
    for i in range(acc.size):
        word = _rom12_word(acc[i], a_word, tsel, rom12, mag_max, shift, addr_bits)
        out[i] = fixed.saturate(fixed.round_shift(c * word, out_shift), 0, out_max)


@njit(cache=True)
def _rom12_path(
    acc: np.ndarray,
    a_word: int,
    tsel: int,
    rom12: np.ndarray,
    mag_max: int,
    shift: int,
    addr_bits: int,
    out: np.ndarray,
) -> None:
    for i in range(acc.size):
        out[i] = _rom12_word(acc[i], a_word, tsel, rom12, mag_max, shift, addr_bits)


class _Tables:
    """ROM contents and derived constants of one configuration, computed once."""

    def __init__(self, cfg: SpecularConfig) -> None:
        self.rom9 = rom9_words(cfg)
        self.rom12 = rom12_words(cfg)
        self.mag_max = (1 << cfg.mag_width) - 1
        self.tsel = np.zeros(1 << N_WIDTH, dtype=np.int64)
        self.tsel[1 : N_MAX + 1] = _table_index(np.arange(1, N_MAX + 1), cfg)
        # What ``_pixels`` needs after (acc, c, a_word, tsel): ROM 12 and the datapath's shifts.
        self.pixel_args = (
            self.rom12,
            self.mag_max,
            cfg.addr_shift,
            cfg.rom_addr_bits,
            cfg.c_frac_bits + cfg.rom_data_bits,
            cfg.out_max,
        )


_TABLES: dict[SpecularConfig, _Tables] = {}


def _tables(cfg: SpecularConfig) -> _Tables:
    if cfg not in _TABLES:
        _TABLES[cfg] = _Tables(cfg)
    return _TABLES[cfg]


def _check_line(c, dz, z0, length, cfg: SpecularConfig) -> tuple[int, int, int, int]:
    c_i = int(fixed.check_operand("c", c, 0, cfg.c_format.hi))
    z_lo, z_hi = cfg.z_format.lo, cfg.z_format.hi
    dz_i = int(fixed.check_operand("dz", dz, z_lo, z_hi))
    z0_i = int(fixed.check_operand("z0", z0, z_lo, z_hi))
    len_i = int(fixed.check_operand("length", length, 0, cfg.len_max))
    return c_i, dz_i, z0_i, len_i


def line_angles(dz: int, z0: int, length: int, cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """The accumulator (register 8) for each of the l+1 pixels, units of 2**-z_frac_bits * pi/2."""
    _, dz_i, z0_i, len_i = _check_line(0, dz, z0, length, cfg)
    acc = np.empty(len_i + 1, dtype=np.int64)
    _accumulate(dz_i, z0_i, len_i, acc)
    return acc


def _run_line(c: int, dz: int, z0: int, n: int, length: int, cfg: SpecularConfig) -> np.ndarray:
    t = _tables(cfg)
    acc = np.empty(length + 1, dtype=np.int64)
    _accumulate(dz, z0, length, acc)
    out = np.empty(length + 1, dtype=np.int64)
    _pixels(acc, c, int(t.rom9[n]), int(t.tsel[n]), *t.pixel_args, out)
    return out


def shade_line(c, dz, z0, n, length, cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """The l+1 output intensities of one line, bit-exact with ``rtl/specular_unit.v``.

    ``c``: C register (unsigned, ``c_frac_bits`` fraction bits, in output LSBs); ``dz``, ``z0``:
    angle registers (signed, units of pi/2 * 2**-z_frac_bits); ``n``: 1..1000; ``length``: the
    number of intervals l (0..2**len_width - 1).  Raises ``ValueError`` for anything outside.
    """
    c_i, dz_i, z0_i, len_i = _check_line(c, dz, z0, length, cfg)
    n_i = int(fixed.check_operand("n", n, 1, N_MAX))
    return _run_line(c_i, dz_i, z0_i, n_i, len_i, cfg)


def unit_line(c, dz, z0, n, length, cfg: SpecularConfig = DEFAULT) -> tuple[np.ndarray, int]:
    """What the RTL does for any 10-bit n: (intensities, n_err).

    For n = 1..1000 this is ``(shade_line(...), 0)``; for n = 0 and n = 1001..1023 the line has
    the same l+1 results at the same cycles, every one 0 with ``n_err`` = 1.
    """
    c_i, dz_i, z0_i, len_i = _check_line(c, dz, z0, length, cfg)
    n_i = int(fixed.check_operand("n", n, 0, (1 << N_WIDTH) - 1))
    if not n_valid(n_i):
        return np.zeros(len_i + 1, dtype=np.int64), 1
    return _run_line(c_i, dz_i, z0_i, n_i, len_i, cfg), 0


def cycles(length, cfg: SpecularConfig = DEFAULT):
    """Clock cycles ``busy`` is high for a line of l intervals: FILL_LATENCY + l.

    The l+1 valid strobes come at ``valid_offsets``; the last one in the first cycle busy is 0,
    when a new start is already accepted: back-to-back lines take l + FILL_LATENCY + 1 clocks.
    Takes an int or an array of interval counts (then returns an array).
    """
    c = FILL_LATENCY + fixed.check_operand("length", length, 0, cfg.len_max)
    return int(c) if c.ndim == 0 else c


def valid_offsets(length, cfg: SpecularConfig = DEFAULT) -> list[int]:
    """Cycle offsets of the valid strobes (0 = the cycle right after the start edge)."""
    len_i = int(fixed.check_operand("length", length, 0, cfg.len_max))
    return list(range(FILL_LATENCY, FILL_LATENCY + len_i + 1))


# ==================================================================== float set-up (host)
_EPS = 1e-12


@dataclass(frozen=True)
class LineSetup:
    """The external device's result for one line: float values and the register words."""

    gamma: float  # angle between H1 and H2' (rad)
    lam: float  # lambda (rad), chosen so the line's angles lie in [-3pi/2, 3pi/2]
    amp: float  # A = max of N1.H on the great circle (>= 0)
    c: float  # C = light * (2**out_width - 1) * A**n, output LSBs
    dz: float  # gamma / l in units of pi/2 (0 for l = 0)
    z0: float  # -lambda in units of pi/2
    c_reg: int
    dz_reg: int
    z0_reg: int
    n: int
    length: int

    def registers(self) -> dict[str, int]:
        """The operand registers of the unit: c, dz, z0, n, len."""
        return {
            "c": self.c_reg,
            "dz": self.dz_reg,
            "z0": self.z0_reg,
            "n": self.n,
            "len": self.length,
        }


def _unit_vector(name: str, v) -> np.ndarray:
    arr = np.asarray(v, dtype=np.float64)
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} = {v!r} is out of range: legal is a finite 3-vector")
    with np.errstate(over="ignore"):
        norm = float(np.linalg.norm(arr))
    if math.isinf(norm):  # (0, 0, 1e300): scale first, then it normalises like any other
        arr = arr / np.abs(arr).max()
        norm = float(np.linalg.norm(arr))
    if norm < _EPS:
        raise ValueError(
            f"{name} = {v!r} is out of range: legal is a non-zero 3-vector (length >= {_EPS:g})"
        )
    return arr / norm


def _scaled_rows(arr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rows, their lengths), rows whose length overflows (a normal (0, 0, 1e300)) first
    divided by their largest component, so that they normalise like any other; the other rows
    are untouched (the same float values as a plain ``arr / norm``)."""
    with np.errstate(over="ignore"):
        norm = np.linalg.norm(arr, axis=1)
    big = np.isinf(norm)
    if big.any():
        arr = arr.copy()
        arr[big] /= np.abs(arr[big]).max(axis=1, keepdims=True)
        norm[big] = np.linalg.norm(arr[big], axis=1)
    return arr, norm


@njit(cache=True)
def _dot3(a: np.ndarray, b: np.ndarray) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True)
def _cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


@njit(cache=True)
def _perpendicular(v: np.ndarray) -> np.ndarray:
    """A fixed unit vector perpendicular to v: v x e, e the coordinate axis least aligned with v."""
    e = np.zeros(3)
    e[int(np.argmin(np.abs(v)))] = 1.0
    p = _cross3(v, e)
    return p / np.sqrt(_dot3(p, p))


@njit(cache=True)
def _rotate_onto(src: np.ndarray, dst: np.ndarray, v: np.ndarray) -> np.ndarray:
    """v rotated by the rotation taking unit vector src onto dst (Rodrigues, axis src x dst).

    R v = c v + s (k x v) + (1 - c) k (k . v).  src = dst: identity.  src = -dst (axis
    undefined): the half turn about the fixed perpendicular ``_perpendicular(dst)``.
    """
    axis = _cross3(src, dst)
    s = np.sqrt(_dot3(axis, axis))
    c = _dot3(src, dst)
    if s < _EPS:
        if c > 0:
            return v.copy()
        u = _perpendicular(dst)
        return 2.0 * _dot3(u, v) * u - v
    k = axis / s
    return c * v + s * _cross3(k, v) + (1.0 - c) * _dot3(k, v) * k


@njit(cache=True)
def _path(n1: np.ndarray, n2: np.ndarray, h1: np.ndarray, h2: np.ndarray):
    """(W, gamma) of ``half_vector_path`` for unit vectors."""
    h2r = _rotate_onto(n2, n1, h2)
    cg = _dot3(h1, h2r)
    w = h2r - cg * h1
    sg = np.sqrt(_dot3(w, w))
    if sg >= 1e-9:
        return w / sg, np.arctan2(sg, cg)
    if cg > 0:
        return np.zeros(3), 0.0
    w = n1 - _dot3(n1, h1) * h1
    wn = np.sqrt(_dot3(w, w))
    if wn >= 1e-9:
        return w / wn, np.pi
    return _perpendicular(h1), np.pi


@njit(cache=True)
def _setup_kernel(
    n1: np.ndarray,
    n2: np.ndarray,
    h1: np.ndarray,
    h2: np.ndarray,
    n: np.ndarray,
    light: np.ndarray,
    length: np.ndarray,
    out_max: int,
    out: np.ndarray,
) -> None:
    """The external device for each row (unit vectors): out[i] = gamma, lambda, A, C, dz, z0.

    See ``setup_line`` for the formulas and the degenerate cases.
    """
    for i in range(n.size):
        w, gamma = _path(n1[i], n2[i], h1[i], h2[i])
        cos1 = _dot3(n1[i], h1[i])
        nw = _dot3(n1[i], w)
        amp = min(1.0, np.hypot(cos1, nw))
        lam = np.arctan2(nw, cos1)
        if gamma / 2 - lam > np.pi:
            lam += 2 * np.pi
        out[i, 0] = gamma
        out[i, 1] = lam
        out[i, 2] = amp
        out[i, 3] = light[i] * out_max * amp ** n[i]
        out[i, 4] = (gamma / length[i]) / (np.pi / 2) if length[i] > 0 else 0.0
        out[i, 5] = -lam / (np.pi / 2)


def rotation_onto(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """The rotation matrix taking unit vector src onto dst (Rodrigues, axis src x dst).

    src = dst: identity.  src = -dst (axis undefined): the half turn about the fixed
    perpendicular ``_perpendicular(dst)``.  Its columns are ``_rotate_onto`` of the basis.
    """
    src, dst = np.asarray(src, dtype=np.float64), np.asarray(dst, dtype=np.float64)
    return np.stack([_rotate_onto(src, dst, e) for e in np.eye(3)], axis=1)


def half_vector_path(n1, n2, h1, h2) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(N1, H1, W, gamma): along the line H(t) = H1 cos(t gamma) + W sin(t gamma), N = N1.

    H2' = H2 rotated by the rotation taking N2 onto N1; gamma = angle(H1, H2'); W the unit vector
    perpendicular to H1 towards H2'.  gamma -> 0: W = 0 (H is constant).  gamma -> pi (H2' =
    -H1, the great circle undefined): W = the part of N1 perpendicular to H1 (the path passes the
    highlight's peak), or a fixed perpendicular if N1 is parallel to H1.
    """
    n1u, n2u = _unit_vector("n1", n1), _unit_vector("n2", n2)
    h1u, h2u = _unit_vector("h1", h1), _unit_vector("h2", h2)
    w, gamma = _path(n1u, n2u, h1u, h2u)
    return n1u, h1u, w, float(gamma)


@dataclass(frozen=True)
class LineSetups:
    """``setup_lines``' result: one row per line, float values and register words."""

    gamma: np.ndarray
    lam: np.ndarray
    amp: np.ndarray
    c: np.ndarray
    dz: np.ndarray
    z0: np.ndarray
    c_reg: np.ndarray
    dz_reg: np.ndarray
    z0_reg: np.ndarray


def _unit_rows(name: str, v) -> np.ndarray:
    arr = np.asarray(v, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 3 or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} is out of range: legal is an (S, 3) array of finite vectors")
    scaled, norm = _scaled_rows(arr)
    if arr.shape[0] and norm.min() < _EPS:
        bad = int(np.argmin(norm))
        raise ValueError(
            f"{name}[{bad}] = {arr[bad].tolist()} is out of range: legal is a non-zero 3-vector "
            f"(length >= {_EPS:g})"
        )
    return scaled / norm[:, None]


def setup_lines(n1, n2, h1, h2, n, light, length, cfg: SpecularConfig = DEFAULT) -> LineSetups:
    """``setup_line`` for S lines at once: (S, 3) end vectors, (S,) n, light and l."""
    vecs = [_unit_rows(name, v) for name, v in (("n1", n1), ("n2", n2), ("h1", h1), ("h2", h2))]
    rows = vecs[0].shape[0]
    if any(v.shape[0] != rows for v in vecs):
        raise ValueError("n1, n2, h1, h2 must have the same number of rows")
    n_arr = np.broadcast_to(fixed.check_operand("n", n, 1, N_MAX), (rows,))
    len_arr = np.broadcast_to(fixed.check_operand("length", length, 0, cfg.len_max), (rows,))
    light_arr = np.broadcast_to(np.asarray(light, dtype=np.float64), (rows,))
    if not np.all(np.isfinite(light_arr)) or (rows and light_arr.min() < 0):
        raise ValueError(f"light = {light!r} is out of range: legal is a finite value >= 0")
    out = np.empty((rows, 6))
    _setup_kernel(
        *vecs,
        np.ascontiguousarray(n_arr, dtype=np.int64),
        np.ascontiguousarray(light_arr),
        np.ascontiguousarray(len_arr, dtype=np.int64),
        cfg.out_max,
        out,
    )
    gamma, lam, amp, c, dz, z0 = out.T
    return LineSetups(
        gamma=gamma,
        lam=lam,
        amp=amp,
        c=c,
        dz=dz,
        z0=z0,
        c_reg=np.asarray(cfg.c_format.quantise(c), dtype=np.int64).reshape(rows),
        dz_reg=np.asarray(cfg.z_format.quantise(dz), dtype=np.int64).reshape(rows),
        z0_reg=np.asarray(cfg.z_format.quantise(z0), dtype=np.int64).reshape(rows),
    )


def setup_line(
    n1, n2, h1, h2, n: int, light: float, length: int, cfg: SpecularConfig = DEFAULT
) -> LineSetup:
    """The float "external device": register values of one line from its end vectors.

    ``n1``, ``h1``: normal and half-vector at the start pixel; ``n2``, ``h2`` at the end pixel
    (normalised here); ``n`` the specular exponent; ``light`` = I_l * k_s (1 = full scale);
    ``length`` the number of intervals l.  N.H(t) = A cos(t gamma - lambda) along the line, so
    I = C cos^n(zeta) with C = light * (2**out_width - 1) * A**n, zeta(0) = -lambda and
    dz = gamma / l.

    With N.W the component of N1 along the path's direction W, A = hypot(cos theta1, N.W) and
    lambda = atan2(N.W, cos theta1): the patent's lambda = arctan P and A = cos theta1 / cos lambda
    whenever cos theta1 > 0, and still defined when cos theta1 <= 0.  lambda is then moved by
    2 pi so that the middle of the line's angles lies in (-pi, pi]: every angle of the line is
    in [-3pi/2, 3pi/2], where cos > 0 exactly for |zeta| < pi/2, the range the unit lights.
    Degenerate cases (each gives finite registers, never NaN): gamma -> 0 (constant H: dz = 0),
    gamma -> pi and N1 = -N2 (see ``half_vector_path`` and ``rotation_onto``), cos theta1 <= 0
    (A, lambda from atan2; A = 0 gives C = 0), l = 0 (dz = 0, one pixel).  C beyond the C
    register saturates.  One implementation with ``setup_lines`` (a one-row batch).
    """
    n_i = int(fixed.check_operand("n", n, 1, N_MAX))
    len_i = int(fixed.check_operand("length", length, 0, cfg.len_max))
    if not isinstance(light, int | float | np.floating) or not math.isfinite(light) or light < 0:
        raise ValueError(f"light = {light!r} is out of range: legal is a finite value >= 0")
    vecs = [
        _unit_vector(name, v)[None, :]
        for name, v in (("n1", n1), ("n2", n2), ("h1", h1), ("h2", h2))
    ]
    rows = setup_lines(*vecs, n_i, float(light), len_i, cfg)
    return LineSetup(
        gamma=float(rows.gamma[0]),
        lam=float(rows.lam[0]),
        amp=float(rows.amp[0]),
        c=float(rows.c[0]),
        dz=float(rows.dz[0]),
        z0=float(rows.z0[0]),
        c_reg=int(rows.c_reg[0]),
        dz_reg=int(rows.dz_reg[0]),
        z0_reg=int(rows.z0_reg[0]),
        n=n_i,
        length=len_i,
    )


def blinn_line(n1, n2, h1, h2, n: int, light: float, length: int, out_max: int = 255) -> np.ndarray:
    """Float reference: light * out_max * max(0, N1.H(t))**n at the l+1 pixels, H(t) on the
    great circle of ``half_vector_path`` (vector arithmetic, no lambda or A involved)."""
    n1u, h1u, w, gamma = half_vector_path(n1, n2, h1, h2)
    t = np.arange(length + 1) / length if length > 0 else np.zeros(1)
    h = np.outer(np.cos(t * gamma), h1u) + np.outer(np.sin(t * gamma), w)
    return light * out_max * np.maximum(h @ n1u, 0.0) ** n


# ==================================================================== fixed-point accuracy
@dataclass(frozen=True)
class Worst:
    """A worst case and registers that reach it: ``shade_line(c, 0, z, n, 0)`` (one pixel, angle
    register z0 = z) gives the output whose distance from the reference is ``value``."""

    value: float
    n: int
    c: int
    z: int


@dataclass(frozen=True)
class Accuracy:
    """Accuracy of one configuration for every n = 1..1000 (arrays indexed n - 1).

    Every figure is a worst case over every input it names (``fixed_point_accuracy`` says why
    the inputs it evaluates are enough); "full scale" is C = 2**out_width - 1 (255).
    """

    float_rel: np.ndarray  # float cos^k(a d) vs cos^n d, epicentre where cos^n >= REL_FLOOR
    rom_rel: np.ndarray  # the ROM-12 word vs cos^n, every angle register value of that range
    out_lsb_exact: np.ndarray  # output vs C max(0, cos)^n, C full scale, |zeta| <= 3pi/2 (LSB)
    out_lsb_approx: np.ndarray  # output vs C cos^k(a zeta), C full scale, every angle (LSB)
    rom_rel_z: np.ndarray  # an angle register value where rom_rel is reached
    out_exact_z: np.ndarray  # ... out_lsb_exact
    out_approx_z: np.ndarray  # ... out_lsb_approx
    approx_c_full: Worst  # output vs C cos^k(a zeta): every n, angle and C <= full scale
    approx_any_c: Worst  # ... every C register value (up to 255.996: the output saturates)
    exact_c_full: Worst  # output vs C max(0, cos)^n: every n, |zeta| <= 3pi/2, C <= full scale
    exact_any_c: Worst  # ... every C register value


REL_FLOOR = 1.0 / 255
"""The relative error of the ROM-12 path is taken where cos^n >= 1/255 (one 8-bit level): only
n = 1's epicentre (the whole quadrant, down to cos = 0) reaches below it."""


def fixed_point_accuracy(cfg: SpecularConfig = DEFAULT) -> Accuracy:
    """The unit against float cos^n and against its float approximation, every n = 1..1000,
    every angle register value (exhaustive; cached per configuration).

    Why evaluating two angles per ROM-12 address is exhaustive: the unit's word depends on the
    angle register z only through the address round(|z| a / 2**addr_shift), so the |z| of one
    address form an integer interval [lo, hi] (computed exactly; past the last address, from
    the overflow on, the word is 0).  On it the word, and for a given C the output, are
    constant, while each reference (cos^n, cos^k(a zeta), both non-increasing in |zeta| on the
    ranges used) is monotone: the distance |constant - reference| is largest at lo or hi.  So
    the ROM-12 path's relative error (|z| from 0 to the last register value in the epicentre
    with cos^n >= ``REL_FLOOR``), the output at full scale against cos^n (|zeta| <= 3pi/2,
    every angle ``setup_line`` produces: beyond it cos^n would rise again) and against
    cos^k(a zeta) (every register value) are exact maxima over every integer angle.  The sign
    does not matter (the unit takes |acc|, the references are even) and the clamp of |zeta|
    before multiplier 11 never changes a word (``mag_int_bits``).

    Every C at once: for one table and address the output round(C w) is fixed by C and the
    word w, and the distance |round(C w) - C f| is linear in the reference value f, so it is
    largest at the smallest or largest f any n of that table reaches at that address (both
    kept).  Every (table, address) gets the bound max(1/2, C_max w - out_max) + C_max |w - f|
    (rounding or saturation, plus the reference's distance); in decreasing order of that bound
    each is scanned over every C register value until the bound cannot beat the worst found.
    ``tests/test_accuracy.py`` checks all of it against a brute force over every n, angle and C
    of a reduced unit, and replays each worst case through ``shade_line``.
    """
    return _accuracy(cfg)


@functools.cache
def _accuracy(cfg: SpecularConfig) -> Accuracy:
    t = _tables(cfg)
    ns = np.arange(1, N_MAX + 1, dtype=np.int64)
    tsel = np.ascontiguousarray(t.tsel[1 : N_MAX + 1])
    ks = np.asarray(cfg.ks, dtype=np.int64)[tsel]
    pairs = list(zip(ns.tolist(), ks.tolist(), strict=True))
    a_float = np.array([alpha_value(n, k, cfg.alpha) for n, k in pairs])
    float_rel = np.array([brdf_max_rel_error(n, k, cfg.alpha, REL_FLOOR) for n, k in pairs])
    size = 1 << cfg.rom_addr_bits
    shape = (2, cfg.num_tables, size + 1)
    f_min, f_max = np.full(shape, np.inf), np.full(shape, -np.inf)
    f_n, f_z = np.zeros((2, *shape), dtype=np.int64), np.zeros((2, *shape), dtype=np.int64)
    per_n = np.zeros((3, N_MAX))
    per_z = np.zeros((3, N_MAX), dtype=np.int64)
    c_full = cfg.out_max << cfg.c_frac_bits
    _exhaustive_angles(
        ns, ks, a_float, np.ascontiguousarray(t.rom9[1 : N_MAX + 1]), tsel, t.rom12,
        cfg.rom_addr_bits, cfg.addr_shift, cfg.z_frac_bits, cfg.rom_data_bits, c_full,
        cfg.c_frac_bits, cfg.out_max, REL_FLOOR, per_n, per_z, f_min, f_max, f_n, f_z,
    )  # fmt: skip
    words = np.zeros((cfg.num_tables, size + 1), dtype=np.int64)
    for j in range(cfg.num_tables):
        words[j, :size] = t.rom12[j * size : (j + 1) * size]
    worst = {}
    for ref in (0, 1):
        for c_lim in (c_full, cfg.c_format.hi):
            value, j, i, c, side = _every_c(
                words, f_min[ref], f_max[ref], c_lim, cfg.c_frac_bits, cfg.rom_data_bits,
                cfg.out_max,
            )  # fmt: skip
            n, z = int(f_n[ref, side, j, i]), int(f_z[ref, side, j, i])
            worst[ref, c_lim] = Worst(float(value), n, int(c), z)
    return Accuracy(
        float_rel=float_rel,
        rom_rel=per_n[0],
        out_lsb_exact=per_n[2],
        out_lsb_approx=per_n[1],
        rom_rel_z=per_z[0],
        out_exact_z=per_z[2],
        out_approx_z=per_z[1],
        approx_c_full=worst[0, c_full],
        approx_any_c=worst[0, cfg.c_format.hi],
        exact_c_full=worst[1, c_full],
        exact_any_c=worst[1, cfg.c_format.hi],
    )


@njit(cache=True)
def _references(z: int, zf: int, n: int, k: int, a: float) -> tuple[float, float]:
    """(cos^k(a zeta) clipped at pi/2, max(0, cos zeta)^n) at angle register value z."""
    zeta = z / 2.0**zf * (np.pi / 2)
    return np.cos(min(a * zeta, np.pi / 2)) ** k, max(np.cos(zeta), 0.0) ** n


@njit(cache=True)
def _in_epicentre(z: int, zf: int, n: int, d_e: float, floor: float) -> bool:
    zeta = z / 2.0**zf * (np.pi / 2)
    return zeta <= d_e and np.cos(zeta) ** n >= floor


@njit(cache=True)
def _epicentre_end(n: int, zf: int, floor: float) -> int:
    """The largest angle register value in the epicentre with cos^n >= floor."""
    d_e = np.pi / 2 if n == 1 else np.arctan(1.0 / np.sqrt(n - 1.0))
    z = int(d_e / (np.pi / 2) * 2.0**zf)
    while _in_epicentre(z + 1, zf, n, d_e, floor):
        z += 1
    while z > 0 and not _in_epicentre(z, zf, n, d_e, floor):
        z -= 1
    return z


@njit(cache=True)
def _extremes(f_min, f_max, f_n, f_z, ref: int, tab: int, i: int, f: float, n: int, z: int):
    """Keep the smallest and largest reference value seen at (table, address), and where."""
    if f < f_min[ref, tab, i]:
        f_min[ref, tab, i] = f
        f_n[ref, 0, tab, i], f_z[ref, 0, tab, i] = n, z
    if f > f_max[ref, tab, i]:
        f_max[ref, tab, i] = f
        f_n[ref, 1, tab, i], f_z[ref, 1, tab, i] = n, z


@njit(cache=True)
def _exhaustive_angles(
    ns: np.ndarray,
    ks: np.ndarray,
    a_float: np.ndarray,
    a_word: np.ndarray,
    tsel: np.ndarray,
    rom12: np.ndarray,
    addr_bits: int,
    shift: int,
    zf: int,
    data_bits: int,
    c_full: int,
    c_frac: int,
    out_max: int,
    floor: float,
    per_n: np.ndarray,
    per_z: np.ndarray,
    f_min: np.ndarray,
    f_max: np.ndarray,
    f_n: np.ndarray,
    f_z: np.ndarray,
) -> None:
    """``fixed_point_accuracy``'s walk over both ends of every address's angle interval.

    per_n[0] / per_z[0]: ROM-12 relative error in the epicentre; [1]: output vs cos^k(a zeta) at
    full scale; [2]: output vs cos^n at full scale.  f_min / f_max[ref, table, address] (ref 0:
    cos^k(a zeta), 1: cos^n), with the n and z reaching them in f_n / f_z[ref, 0 (min) | 1].
    """
    size = 1 << addr_bits
    half = 1 << (shift - 1)
    z_cap = 3 << zf  # |zeta| <= 3 pi/2: where the exact reference is compared
    out_shift = c_frac + data_bits
    c_val = c_full / 2.0**c_frac
    for j in range(ns.size):
        n, k, a, aw, tab = ns[j], ks[j], a_float[j], a_word[j], tsel[j]
        z_rel = _epicentre_end(n, zf, floor)
        for i in range(size + 1):
            num = (i << shift) - half
            lo = 0 if num <= 0 else (num + aw - 1) // aw  # the least |z| with address i
            if i < size:
                hi = (((i + 1) << shift) - half + aw - 1) // aw - 1
                word = rom12[(tab << addr_bits) | i]
            else:  # overflow (a |zeta| >= pi/2): 0 from lo on, for every larger |z|
                hi = max(lo, z_cap)
                word = 0
            if lo > hi:
                continue
            out = min(fixed.round_shift(c_full * word, out_shift), out_max)
            for end in range(2):
                z = lo if end == 0 else hi
                approx = _references(z, zf, n, k, a)[0]
                if i == size and end == 1:
                    approx = 0.0  # far past pi/2 (a |zeta| >= pi/2) the approximation is 0
                err = abs(out - c_val * approx)
                if err > per_n[1, j]:
                    per_n[1, j], per_z[1, j] = err, z
                _extremes(f_min, f_max, f_n, f_z, 0, tab, i, approx, n, z)
                if lo <= z_cap:  # the exact reference on the part with |zeta| <= 3pi/2
                    z = min(z, z_cap)
                    exact = _references(z, zf, n, k, a)[1]
                    err = abs(out - c_val * exact)
                    if err > per_n[2, j]:
                        per_n[2, j], per_z[2, j] = err, z
                    _extremes(f_min, f_max, f_n, f_z, 1, tab, i, exact, n, z)
            if lo <= z_rel:  # (the overflow's word 0 too: a relative error of 1)
                for end in range(2):
                    z = lo if end == 0 else min(hi, z_rel)
                    exact = _references(z, zf, n, k, a)[1]
                    rel = abs(word / 2.0**data_bits / exact - 1.0)
                    if rel > per_n[0, j]:
                        per_n[0, j], per_z[0, j] = rel, z


@njit(cache=True)
def _every_c(
    words: np.ndarray,
    f_min: np.ndarray,
    f_max: np.ndarray,
    c_lim: int,
    c_frac: int,
    data_bits: int,
    out_max: int,
):
    """max over (table, address) and C register c = 0..c_lim of |out(c, word) - C f|, f the
    smallest or largest reference value at that address: (value, table, address, c, 0 | 1)."""
    tables, count = words.shape
    bound = np.full(tables * count, -1.0)
    c_top = c_lim / 2.0**c_frac
    for j in range(tables):
        for i in range(count):
            if f_max[j, i] >= f_min[j, i]:
                u = words[j, i] / 2.0**data_bits
                residue = max(0.5, c_top * u - out_max)  # rounding, or saturation
                far = max(abs(u - f_min[j, i]), abs(u - f_max[j, i]))
                bound[j * count + i] = residue + c_top * far
    best, best_j, best_i, best_c, best_side = -1.0, 0, 0, 0, 0
    for idx in np.argsort(-bound):
        if bound[idx] <= best:
            break
        j, i = idx // count, idx % count
        word, lo_f, hi_f = words[j, i], f_min[j, i], f_max[j, i]
        for c in range(c_lim + 1):
            out = min(fixed.round_shift(c * word, c_frac + data_bits), out_max)
            cv = c / 2.0**c_frac
            for side in range(2):
                err = abs(out - cv * (lo_f if side == 0 else hi_f))
                if err > best:
                    best, best_j, best_i, best_c, best_side = err, j, i, c, side
    return best, best_j, best_i, best_c, best_side


def approx_lsb_bound(n: int, cfg: SpecularConfig = DEFAULT) -> float:
    """An analytic bound on |output - C cos^k(a zeta)| at full scale (and any C below it):
    1/2 (output rounding) + C (2**-D (table rounding, the 1.0 saturated) + S_k pi/2 e), e the
    error of the scaled angle in units of pi/2: half an address step plus |zeta| times the
    rounding of a in ROM 9, at the largest |zeta| where either side is not yet 0."""
    k = decode_k(n, cfg)
    a = alpha_value(n, k, cfg.alpha)
    zeta_max = 1.0 / (a - 2.0 ** -(cfg.a_frac_bits + 1))
    angle = 2.0 ** -(cfg.rom_addr_bits + 1) + zeta_max * 2.0 ** -(cfg.a_frac_bits + 1)
    slope = cos_power_max_slope(k)
    return 0.5 + cfg.out_max * (2.0**-cfg.rom_data_bits + slope * math.pi / 2 * angle)


def angle_drift_steps(cfg: SpecularConfig = DEFAULT) -> float:
    """The largest error of the accumulated angle over the longest line, in ROM-12 address
    steps of the largest a: dz and z0 each rounded by at most half an LSB, so after l <= len_max
    intervals |acc - (z0 + l dz)| <= (l + 1) 2**-(z_frac_bits+1); reached exactly when both sit
    half an LSB off the grid the same way (``angle_drift_example``)."""
    a_max = int(rom9_words(cfg).max()) / 2.0**cfg.a_frac_bits
    return (cfg.len_max + 1) * 2.0 ** -(cfg.z_frac_bits + 1) * a_max * 2.0**cfg.rom_addr_bits


def angle_drift_example(cfg: SpecularConfig = DEFAULT) -> float:
    """The drift (address steps, largest a) of a line whose exact z0 and dz both lie exactly
    half an LSB above a grid point: the register values the host's rounding (half away from
    zero) gives, run through ``line_angles``, against the exact angles."""
    lsb = 2.0**-cfg.z_frac_bits
    z0, dz = 1000.5 * lsb, 777.5 * lsb  # exact values, both ties
    fmt = cfg.z_format
    acc = line_angles(fmt.quantise(dz), fmt.quantise(z0), cfg.len_max, cfg)
    exact = (1000.5 + 777.5 * np.arange(cfg.len_max + 1)) * lsb
    a_max = int(rom9_words(cfg).max()) / 2.0**cfg.a_frac_bits
    return float(np.max(np.abs(acc * lsb - exact)) * a_max * 2**cfg.rom_addr_bits)


# ==================================================================== report tables (README)
N_RANGES = ((1, 1), (2, 2), (3, 6), (7, 7), (8, 1000), (1000, 1000))


def _worst(values: np.ndarray, lo: int, hi: int) -> tuple[float, int]:
    part = values[lo - 1 : hi]
    i = int(np.argmax(part))
    return float(part[i]), lo + i


def _up(value: float, digits: int, scale: int = 1) -> str:
    return fixed.format_up(value, digits, scale)


def float_errors(cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """brdf_max_rel_error of the configuration's mapping (its k and alpha) for n = 1..1000."""
    ks = decode_k(np.arange(1, N_MAX + 1), cfg)
    return np.array([brdf_max_rel_error(n, int(k), cfg.alpha) for n, k in enumerate(ks, 1)])


SINGLE_TABLES = (
    ("cos (prototype's k = 1)", 1, "taylor", 2),
    ("cos^2 (prototype)", 2, "taylor", 3),
    ("cos^2", 2, "inflection", 3),
    ("cos^3", 3, "taylor", 4),
    ("cos^3", 3, "inflection", 4),
    ("cos^16", 16, "taylor", 17),
    ("cos^16", 16, "inflection", 17),
)
"""Single-table approximations: (label, k, alpha, smallest n), worst over n = that..1000."""


def single_table_worst(k: int, alpha: str, lo: int) -> tuple[float, int]:
    """The worst ``brdf_max_rel_error`` of one cos^k table over n = lo..1000, and its n."""
    errs = np.array([brdf_max_rel_error(n, k, alpha) for n in range(lo, N_MAX + 1)])
    i = int(np.argmax(errs))
    return float(errs[i]), lo + i


def format_brdf_table() -> str:
    """The float approximation's worst relative error in the epicentre, per n range (markdown;
    exact maxima, rounded up)."""
    taylor = float_errors(DEFAULT)
    infl = float_errors(INFLECTION)
    lines = [
        "| n | k | a = sqrt(n/k) (patent): worst | at n | a exact at the inflection point "
        "(thesis): worst | at n |",
        "|---|---|---|---|---|---|",
    ]
    for lo, hi in N_RANGES:
        k = decode_k(lo)
        (t, tn), (f, fn) = _worst(taylor, lo, hi), _worst(infl, lo, hi)
        rng = str(lo) if lo == hi else f"{lo}..{hi}"
        lines.append(f"| {rng} | {k} | {_up(t, 3, 100)} % | {tn} | {_up(f, 3, 100)} % | {fn} |")
    lines += ["", "| single table | a | worst over n | at n |", "|---|---|---|---|"]
    for label, k, alpha, lo in SINGLE_TABLES:
        worst, at = single_table_worst(k, alpha, lo)
        lines.append(f"| {label} | {alpha} | {_up(worst, 3, 100)} % | {at} |")
    return "\n".join(lines)


def format_accuracy_table(cfg: SpecularConfig = DEFAULT, acc: Accuracy | None = None) -> str:
    """The fixed-point unit against float cos^n, per n range (markdown; worst cases over every
    angle register value, rounded up)."""
    acc = fixed_point_accuracy(cfg) if acc is None else acc
    full = cfg.out_max
    lines = [
        "| n | float approximation (epicentre) | ROM-12 path vs cos^n (epicentre) "
        f"| output vs C cos^n (LSB, C = {full}) | output vs C cos^k(a d) (LSB, C = {full}) |",
        "|---|---|---|---|---|",
    ]
    for lo, hi in N_RANGES:
        rng = str(lo) if lo == hi else f"{lo}..{hi}"
        cells = [
            f"{_up(_worst(acc.float_rel, lo, hi)[0], 4, 100)} %",
            f"{_up(_worst(acc.rom_rel, lo, hi)[0], 4, 100)} %",
            _up(_worst(acc.out_lsb_exact, lo, hi)[0], 4),
            _up(_worst(acc.out_lsb_approx, lo, hi)[0], 4),
        ]
        lines.append(f"| {rng} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def format_config_table(accs: dict[str, Accuracy]) -> str:
    """Worst figures over n = 1..1000 for several configurations (markdown, rounded up)."""
    lines = [
        "| config | tables | ROM 12 | worst ROM-12 path vs cos^n (n >= 2) | at n "
        "| output vs C cos^n (LSB): C = full scale | any C <= full scale | any C "
        "| output vs C cos^k(a d) (LSB): C = full scale | any C <= full scale | any C |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, acc in accs.items():
        cfg = ROM_CONFIGS[name]
        rom_worst, rom_n = _worst(acc.rom_rel, 2, N_MAX)
        cells = [
            acc.out_lsb_exact.max(),
            acc.exact_c_full.value,
            acc.exact_any_c.value,
            acc.out_lsb_approx.max(),
            acc.approx_c_full.value,
            acc.approx_any_c.value,
        ]
        lines.append(
            f"| {name} | k = {', '.join(map(str, cfg.ks))} ({cfg.alpha}) "
            f"| {cfg.num_tables} x 2^{cfg.rom_addr_bits} x {cfg.rom_data_bits} bits "
            f"| {_up(rom_worst, 4, 100)} % | {rom_n} | "
            + " | ".join(_up(v, 4) for v in cells)
            + " |"
        )
    return "\n".join(lines)
