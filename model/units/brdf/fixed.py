# SPDX-License-Identifier: Apache-2.0
"""BRDF family: bit-exact fixed-point models of the thesis's five forms of cos^n d.

Owns ``FixedConfig`` (one frozen configuration per form: table, coefficient, work and output
widths, validated by name), the ROM contents (``rom_images``: the angle table, the coefficient
table per n, the log2 form's second table) and their size (``table_bits``), and the numba
kernels that compute what the hardware would (``evaluate``: the output word for angle register
values and an n).  The float forms of ``approx`` are the references the kernels approximate;
``fixed_accuracy`` measures how well, exhaustively.  May import numpy, numba,
``model.units.fixed``, ``model.units.specular``'s public names and ``approx``.

Every form takes the same steps in front (the patent's unit, fig. 1, up to ROM 12):
* the angle: the specular unit's accumulator (register 8, ``angle.z_format``: units of pi/2,
  two's complement, ``angle.z_frac_bits`` fraction bits), taken as |z| (every form is even);
* the angle table (``cos_addr_bits`` = A, ``cos_data_bits`` = D): addressed, as ROM 12 is, by
  |z| rounded to A fraction bits (add half, slice); an address of 2**A or more is pi/2 or beyond
  and reads as cos = 0 (never wrapped).  It holds the cosine of the angle as w = 1 - cos
  (``round(2 sin^2(x/2) 2**D)``, D fraction bits): every form needs 1 - cos, and the complement
  is exact at 0 where a cos word would saturate at 1 - 2**-D (which would cost n 2**-D of
  relative error at d = 0).  The log2 form's table holds -log2 cos instead (the thesis
  tabulates log2 cos);
* per n, a coefficient table (like ROM 9) holds the form's coefficients, each an unsigned
  fixed-point word of ``coef_bits`` bits whose integer bits are the fewest its largest value
  over n = 1..1000 needs (``coef_formats``);
* the form's arithmetic, with ``work_bits`` = P fraction bits for every intermediate value:
  products are exact and rounded to P fraction bits (add half, slice: ``fixed.round_shift``),
  sums of aligned words are exact;
* the output: [0, 1] in ``out_bits`` = O fraction bits, rounded (add half, slice), negative
  values clipped to 0 and 1.0 saturated to 2**O - 1 (as ROM 12's words are).
``evaluate`` and the kernels' docstrings give each form's datapath.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from model.units import fixed
from model.units.brdf.approx import (
    FORMS,
    bloom_coefficients,
    check_n,
    cubic_coefficients,
    quadratic_coefficients,
)
from model.units.specular import DEFAULT, N_MAX, SpecularConfig

COEFFICIENTS: dict[str, tuple[str, ...]] = {
    "quadratic": ("a",),
    "cubic": ("r", "p0", "b1", "b2"),
    "piecewise": ("r", "p0", "b1", "b2", "s2", "beta"),
    "log2": (),
    "cosine_quadratic": (),
}
"""The coefficient table's words per n, per form (the log2 form multiplies by the n register
itself, the cosine-quadratic by 7n/16, computed: neither has a coefficient table)."""
TAU_INT_BITS = 5
"""The cubic's scaled distance tau = 1 - r w is saturated to signed Q5.P, [-16, 16): in the
epicentre tau lies in [0, 1], and the bound keeps tau (b1 + b2 tau) within the 62-bit kernels."""
LOG2COS_INT_BITS = 2
"""The log2 form's angle table holds -log2 cos in unsigned Q2.(D - 2), saturated below 4: from
-log2 cos >= 3 on the form is 0 for every n >= 1."""


def coefficient_values(form: str, n: int) -> tuple[float, ...]:
    """The float coefficients the table holds for n, in ``COEFFICIENTS[form]``'s order.

    Cubic: the thesis's c P(c), P = p0 + p1 (c - s) + a1 (c - s)^2, rewritten in the scaled
    distance tau = (c - s) / (1 - s) = 1 - r w (w = 1 - c, r = 1 / (1 - s)):
    P = p0 + b1 tau + b2 tau^2 with b1 = p1 (1 - s), b2 = a1 (1 - s)^2, all within [0, 1]
    (a1 reaches 3.2e5 and p1 999 at n = 1000: a fixed-point word could not hold them with the
    precision small n need), r up to 1443.  Piecewise: the cubic's, then the bloom part's
    denominator alpha - beta c = 2 s + 2 (n - 1) (w - (1 - s)) = s2 - beta' tau with s2 = 2 s and
    beta' = 2 (n - 1) (1 - s) (at most 2 ln 2)."""
    if form == "quadratic":
        return (quadratic_coefficients(n).a,)
    if form in ("cubic", "piecewise"):
        k = cubic_coefficients(n)
        g = 1.0 - k.cos_t
        values = (1.0 / g, k.p0, k.p1 * g, k.a1 * g * g)
        if form == "cubic":
            return values
        s = bloom_coefficients(n).cos_t
        return (*values, 2.0 * s, 2.0 * (n - 1) * (1.0 - s))
    return ()


@functools.cache
def _coefficient_table(form: str) -> np.ndarray:
    """The float coefficients of n = 1..1000, one row per n (shape (1000, words))."""
    names = COEFFICIENTS[form]
    return np.array(
        [coefficient_values(form, n) for n in range(1, N_MAX + 1)], dtype=np.float64
    ).reshape(N_MAX, len(names))


def _int_bits(largest: float, bits: int) -> int:
    """The fewest integer bits e with round(largest 2**(bits - e)) < 2**bits."""
    e = 0
    while e < bits and math.floor(largest * 2.0 ** (bits - e) + 0.5) >= 1 << bits:
        e += 1
    return e


@dataclass(frozen=True)
class FixedConfig:
    """The widths of one form's fixed-point unit (defaults: the widths docs/brdf.md measures).

    ``angle`` gives the angle register's format (the specular unit's accumulator); the others:
    ``cos_addr_bits`` (A) and ``cos_data_bits`` (D) the angle table, ``coef_bits`` each
    coefficient word, ``work_bits`` (P) the fraction bits of every intermediate value,
    ``out_bits`` (O) the output's, ``log_addr_bits`` / ``log_data_bits`` the log2 form's second
    table (log2(1 + f), f in [0, 1)); unused fields are checked but change nothing.
    """

    form: str = "quadratic"
    cos_addr_bits: int = 12
    cos_data_bits: int = 20
    coef_bits: int = 18
    work_bits: int = 24
    out_bits: int = 16
    log_addr_bits: int = 10
    log_data_bits: int = 16
    angle: SpecularConfig = field(default=DEFAULT)

    def __post_init__(self) -> None:
        if self.form not in FORMS:
            raise ValueError(f"form = {self.form!r} is out of range: legal forms are {FORMS}")
        if not isinstance(self.angle, SpecularConfig):
            raise ValueError(f"angle = {self.angle!r} is out of range: legal is a SpecularConfig")
        fixed.check_width("cos_addr_bits", self.cos_addr_bits, 2, min(16, self.angle.z_frac_bits))
        fixed.check_width("cos_data_bits", self.cos_data_bits, 4, 24)
        fixed.check_width("coef_bits", self.coef_bits, 4, 32)
        fixed.check_width("work_bits", self.work_bits, 4, 28)
        fixed.check_width("out_bits", self.out_bits, 1, 24)
        fixed.check_width("log_addr_bits", self.log_addr_bits, 2, 16)
        fixed.check_width("log_data_bits", self.log_data_bits, 4, 24)
        for name, width in self.product_widths.items():
            if width > fixed.MAX_KERNEL_WIDTH:
                raise ValueError(
                    f"{name} = {width} is out of range: at most {fixed.MAX_KERNEL_WIDTH} bits"
                )

    # ---------------------------------------------------------------- derived formats
    @property
    def coefficients(self) -> tuple[str, ...]:
        return COEFFICIENTS[self.form]

    @property
    def widths_read(self) -> tuple[str, ...]:
        """The width fields the form's arithmetic reads, in field order: the others are
        checked but change nothing (a form without coefficients ignores ``coef_bits``, the log2
        form ``work_bits``, every other form the log2 table's two)."""
        names = ["cos_addr_bits", "cos_data_bits"]
        if self.coefficients:
            names.append("coef_bits")
        if self.form != "log2":
            names.append("work_bits")
        names.append("out_bits")
        if self.form == "log2":
            names += ["log_addr_bits", "log_data_bits"]
        return tuple(names)

    @property
    def coef_formats(self) -> dict[str, fixed.QFormat]:
        """Each coefficient's unsigned Qe.f, e + f = ``coef_bits``, e the fewest integer bits
        its largest value over n = 1..1000 rounds into."""
        table = _coefficient_table(self.form)
        return {
            name: fixed.QFormat(e, self.coef_bits - e, signed=False)
            for j, name in enumerate(self.coefficients)
            for e in [_int_bits(float(table[:, j].max()), self.coef_bits)]
        }

    @property
    def addr_shift(self) -> int:
        """Bits of |z| dropped to form the angle table's address."""
        return self.angle.z_frac_bits - self.cos_addr_bits

    @property
    def product_widths(self) -> dict[str, int]:
        """The widest product (signed bits) each step forms: every one must fit the kernels."""
        d, p, c, o = self.cos_data_bits, self.work_bits, self.coef_bits, self.out_bits
        widths = {
            "quadratic": {"a x w": c + d + 1, "c x (1 - a w)": d + p + 2},
            "cubic": {
                "r x w": c + d + 1,
                "b2 x tau": c + p + TAU_INT_BITS + 1,
                "tau x (b1 + b2 tau)": 2 * (p + TAU_INT_BITS) + 2,
                "c x P": d + p + TAU_INT_BITS + 8,
            },
            "log2": {"n x -log2 cos": d + 10, "1 - log2(u) / 2": self.log_data_bits + o + 2},
            "cosine_quadratic": {"7n x w": d + 14, "(1 - m w)^2": 2 * p + 2},
        }
        r_int = self.coef_formats["r"].int_bits if self.form == "piecewise" else 0
        widths["piecewise"] = {
            **widths["cubic"],
            "beta x (r w - 1)": c + r_int + p + 2,
            "2 c / (s2 - beta tau), numerator": p + o + 3,
        }
        return widths[self.form]


# ==================================================================== tables
def angle_table(cfg: FixedConfig) -> np.ndarray:
    """The angle table (like ROM 12, addressed by the angle rounded to A fraction bits of pi/2):
    2**A words, word i for the angle x = i 2**-A pi/2.  Every form but log2: w = 1 - cos x as
    round(2 sin^2(x/2) 2**D) (free of cancellation; below 1, so never saturated for D <= 24);
    log2: round(-log2(cos x) 2**(D - 2)) saturated to 2**D - 1 (``LOG2COS_INT_BITS``)."""
    a, d = cfg.cos_addr_bits, cfg.cos_data_bits
    x = np.arange(1 << a, dtype=np.float64) * (np.pi / 2) / 2**a
    if cfg.form == "log2":
        value = -np.log2(np.cos(x)) * 2.0 ** (d - LOG2COS_INT_BITS)
    else:
        value = 2.0 * np.sin(x / 2) ** 2 * 2.0**d
    return np.minimum(np.floor(value + 0.5), (1 << d) - 1).astype(np.int64)


def log2_table(cfg: FixedConfig) -> np.ndarray:
    """The log2 form's second table (the log2 device of fig. 9b): round(log2(1 + j 2**-E)
    2**L) for j < 2**E (E = ``log_addr_bits``, L = ``log_data_bits``), below 1 so never saturated;
    an address rounded up to 2**E is the next octave (log2 = 1 more, word 0)."""
    e, d = cfg.log_addr_bits, cfg.log_data_bits
    f = np.arange(1 << e, dtype=np.float64) / 2**e
    return np.floor(np.log2(1.0 + f) * 2.0**d + 0.5).astype(np.int64)


def coefficient_words(cfg: FixedConfig) -> np.ndarray:
    """The coefficient table: row n - 1 holds round(x 2**f) of each of n's coefficients, in
    ``cfg.coefficients``' order (Qe.f of ``coef_formats``); shape (1000, words)."""
    table = _coefficient_table(cfg.form)
    fracs = np.array([q.frac_bits for q in cfg.coef_formats.values()], dtype=np.float64)
    return np.floor(table * 2.0**fracs + 0.5).astype(np.int64).reshape(table.shape)


def rom_images(cfg: FixedConfig) -> dict[str, np.ndarray]:
    """Every table of the unit as integer words: ``"angle"`` (``angle_table``), ``"coef"``
    (``coefficient_words``, when the form has coefficients), ``"log2"`` (log2 form)."""
    images = {"angle": angle_table(cfg)}
    if cfg.coefficients:
        images["coef"] = coefficient_words(cfg)
    if cfg.form == "log2":
        images["log2"] = log2_table(cfg)
    return images


def table_bits(cfg: FixedConfig) -> dict[str, int]:
    """Bits per table and their ``"total"``: the angle table 2**A x D, the coefficient table
    1000 x (words x ``coef_bits``), the log2 table 2**E x L."""
    bits = {"angle": (1 << cfg.cos_addr_bits) * cfg.cos_data_bits}
    if cfg.coefficients:
        bits["coef"] = N_MAX * len(cfg.coefficients) * cfg.coef_bits
    if cfg.form == "log2":
        bits["log2"] = (1 << cfg.log_addr_bits) * cfg.log_data_bits
    bits["total"] = sum(bits.values())
    return bits


# ==================================================================== kernels
@njit(cache=True, inline="always")
def _address(z: int, shift: int, addr_bits: int) -> int:
    """|z| rounded to the table's A fraction bits (add half, slice); 2**A means pi/2 or more."""
    addr = fixed.round_shift(abs(z), shift)
    return min(addr, 1 << addr_bits)


@njit(cache=True, inline="always")
def _w(z: int, table: np.ndarray, shift: int, addr_bits: int, d: int) -> int:
    """w = 1 - cos |z| from the angle table (D fraction bits); 2**D (cos = 0) from pi/2 on."""
    addr = _address(z, shift, addr_bits)
    return (1 << d) if addr >= (1 << addr_bits) else table[addr]


@njit(cache=True, inline="always")
def _output(value: int, shift: int, out_bits: int) -> int:
    """round(value / 2**shift) (add half, slice), clipped to [0, 2**O - 1]."""
    return fixed.saturate(fixed.round_shift(value, shift), 0, (1 << out_bits) - 1)


@njit(cache=True)
def quadratic_kernel(z, table, coef, fa, shift, a_bits, d, p, o, out) -> None:
    """a c^2 + (1 - a) c = c (1 - a w): m = a w rounded to P fraction bits; 1 - m clipped at 0
    (the float form's max(0, ...): c >= 0); c = 1 - w (exact) times it, rounded to O bits.
    Two multipliers and a subtractor, one coefficient per n (fig. 9a)."""
    one = 1 << p
    for i in range(z.size):
        w = _w(z[i], table, shift, a_bits, d)
        m = fixed.round_shift(coef[0] * w, fa[0] + d - p)
        out[i] = _output(((1 << d) - w) * max(0, one - m), d + p - o, o)


@njit(cache=True, inline="always")
def _tau(w: int, r: int, fr: int, d: int, p: int) -> tuple[int, int]:
    """(r w rounded to P fraction bits, tau = 1 - r w)."""
    rw = fixed.round_shift(r * w, fr + d - p)
    return rw, (1 << p) - rw


@njit(cache=True, inline="always")
def _cubic_value(w: int, tau: int, coef, fa, d: int, p: int, o: int) -> int:
    """c (p0 + tau (b1 + b2 tau)), Horner, each product rounded to P fraction bits; tau
    saturated to [-16, 16) (``TAU_INT_BITS``); P clipped at 0, the output rounded to O bits."""
    bound = 1 << (p + TAU_INT_BITS - 1)
    t = fixed.saturate(tau, -bound, bound - 1)
    h = fixed.round_shift(coef[3] * t, fa[3]) + fixed.round_shift(coef[2], fa[2] - p)
    poly = fixed.round_shift(t * h, p) + fixed.round_shift(coef[1], fa[1] - p)
    return _output(((1 << d) - w) * max(0, poly), d + p - o, o)


@njit(cache=True)
def cubic_kernel(z, table, coef, fa, shift, a_bits, d, p, o, out) -> None:
    """The cubic c P(c) about the match point s: tau = 1 - r w (r = 1/(1 - s), the product
    rounded to P bits), P = p0 + tau (b1 + b2 tau) (``_cubic_value``), times c, rounded.
    Three multipliers for P and one for c; four coefficients per n."""
    for i in range(z.size):
        w = _w(z[i], table, shift, a_bits, d)
        out[i] = _cubic_value(w, _tau(w, coef[0], fa[0], d, p)[1], coef, fa, d, p, o)


@njit(cache=True)
def piecewise_kernel(z, table, coef, fa, shift, a_bits, d, p, o, out) -> None:
    """The cubic where tau > 0 (c > s, cos^n > 0.5: the whole epicentre), else the bloom part
    c / (s2 + beta (r w - 1)): the denominator's product rounded to P bits, the quotient
    rounded to O bits (round half up: (2 num + den) // (2 den), exact: the numerator or the
    denominator is shifted to align them, never truncated), a divider's result."""
    for i in range(z.size):
        w = _w(z[i], table, shift, a_bits, d)
        rw, tau = _tau(w, coef[0], fa[0], d, p)
        if tau > 0:
            out[i] = _cubic_value(w, tau, coef, fa, d, p, o)
            continue
        den = fixed.round_shift(coef[4], fa[4] - p)
        den += fixed.round_shift(coef[5] * (rw - (1 << p)), fa[5])
        num = (1 << d) - w  # c, D fraction bits: c / den has D - P, the result O
        if p + o >= d:
            num <<= p + o - d
        else:
            den <<= d - p - o
        q = (2 * num + den) // (2 * den)
        out[i] = fixed.saturate(q, 0, (1 << o) - 1)


@njit(cache=True)
def log2_kernel(z, table, logt, n, shift, a_bits, d, e_bits, l_bits, o, out) -> None:
    """2^(n log2 c) ~ 1 - log2(1 + x) / 2, x = n (-log2 c) (exact: the n register times the
    table word, D - 2 fraction bits); 0 once x >= 3.  u = 1 + x in [1, 4) is taken as
    2^e (1 + f): f rounded to E bits addresses the log2 table (the same log2 device, fig. 9b),
    log2 u = e + table (L fraction bits; an address rounded up to 2**E is the next octave);
    1 - log2(u) / 2 rounded to O bits."""
    uf = d - LOG2COS_INT_BITS  # fraction bits of the table word, x and u
    for i in range(z.size):
        addr = _address(z[i], shift, a_bits)
        word = (1 << d) - 1 if addr >= (1 << a_bits) else table[addr]
        x = n * word
        if x >= 3 << uf:
            out[i] = 0
            continue
        u = (1 << uf) + x
        octave = 0 if u < (2 << uf) else 1
        j = fixed.round_shift(u - (1 << (uf + octave)), uf + octave - e_bits)
        if j >= 1 << e_bits:
            octave, j = octave + 1, 0
        lg = (octave << l_bits) + logt[j]
        out[i] = _output((1 << (l_bits + 1)) - lg, l_bits + 1 - o, o)


@njit(cache=True)
def cosine_quadratic_kernel(z, table, n, shift, a_bits, d, p, o, out) -> None:
    """(1 - (7n/16) w)^2: 7n (exact, 4 fraction bits) times w, rounded to P bits; 1 - m w
    clipped at 0; squared (one multiplier), rounded to O bits.  No coefficient table (fig. 9c)."""
    one = 1 << p
    for i in range(z.size):
        w = _w(z[i], table, shift, a_bits, d)
        base = max(0, one - fixed.round_shift(7 * n * w, 4 + d - p))
        out[i] = _output(base * base, 2 * p - o, o)


# ==================================================================== the unit
class Unit:
    """One configuration's tables and constants, computed once (``unit``)."""

    def __init__(self, cfg: FixedConfig) -> None:
        self.cfg = cfg
        self.images = rom_images(cfg)
        self.fracs = np.array([q.frac_bits for q in cfg.coef_formats.values()], dtype=np.int64)


@functools.cache
def unit(cfg: FixedConfig) -> Unit:
    """The ``Unit`` of ``cfg`` (built on first use, then shared)."""
    return Unit(cfg)


def evaluate(cfg: FixedConfig, z, n: int) -> np.ndarray:
    """The output words (O fraction bits: 2**O - 1 is full scale) of ``cfg``'s unit at the
    angle register values ``z`` (the accumulator's format, ``cfg.angle``) for n = 1..1000.

    Bit-exact integer arithmetic (numba); the float reference is ``approx.approximate(cfg.form,
    z 2**-zf pi/2, n)``.  Raises ``ValueError`` naming a bad z or n."""
    n = check_n(n)
    acc = cfg.angle
    lo, hi = fixed.signed_range(acc.acc_width)
    zs = np.ascontiguousarray(fixed.check_operand("z", z, lo, hi).reshape(-1))
    return _run(cfg, zs, n).reshape(np.shape(z))


def _run(cfg: FixedConfig, zs: np.ndarray, n: int) -> np.ndarray:
    u = unit(cfg)
    out = np.empty(zs.size, dtype=np.int64)
    table, args = u.images["angle"], (cfg.addr_shift, cfg.cos_addr_bits, cfg.cos_data_bits)
    p, o = cfg.work_bits, cfg.out_bits
    if cfg.form == "log2":
        e, bits = cfg.log_addr_bits, cfg.log_data_bits
        log2_kernel(zs, table, u.images["log2"], n, *args, e, bits, o, out)
    elif cfg.form == "cosine_quadratic":
        cosine_quadratic_kernel(zs, table, n, *args, p, o, out)
    else:
        kernel = {
            "quadratic": quadratic_kernel,
            "cubic": cubic_kernel,
            "piecewise": piecewise_kernel,
        }[cfg.form]
        kernel(zs, table, np.ascontiguousarray(u.images["coef"][n - 1]), u.fracs, *args, p, o, out)
    return out


QUADRATIC = FixedConfig("quadratic")
CUBIC = FixedConfig("cubic")
PIECEWISE = FixedConfig("piecewise")
LOG2 = FixedConfig("log2")
COSINE_QUADRATIC = FixedConfig("cosine_quadratic")
CONFIGS: dict[str, FixedConfig] = {
    "quadratic": QUADRATIC,
    "cubic": CUBIC,
    "piecewise": PIECEWISE,
    "log2": LOG2,
    "cosine_quadratic": COSINE_QUADRATIC,
}
"""The widths docs/brdf.md measures, per form (angle table 2^12 x 20 bits, 18-bit coefficients,
24 work bits, 16-bit output; the log2 form's second table 2^10 x 16 bits)."""
