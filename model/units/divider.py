# SPDX-License-Identifier: Apache-2.0
"""Shift-add divider (Romanyuk & Obidnyk, docs/divider.md): a / k as a * sum of 2**-j.

The reciprocal 1/k is stored as the ROM word ``r = round(2**N / k)`` (N = ``recip_bits``), whose
set bits are the terms i_j / 2**j of the article.  The unit loads the dividend into a shift
register that carries N extra fraction bits, shifts it one place right per clock and adds it into
an accumulator wherever the current reciprocal bit is 1.  Because the shift register keeps every
bit, the quotient is exactly ``a * r`` in units of 2**-N: the only error is that of ``r`` itself.

Formats:
* dividend ``a``: signed integer of ``a_width`` bits (whatever scale the caller gives it);
* divisor ``k``: unsigned, ``k_width`` bits, 1..2**k_width - 1 (the RTL flags 0 as ``div_zero``);
* reciprocal ``r``: unsigned, ``recip_bits + 1`` bits (k = 1 needs the 2**0 term);
* quotient ``q``: signed, ``a_width + recip_bits`` bits, ``recip_bits`` of them fraction bits:
  the value is ``q / 2**recip_bits`` in the dividend's units.

Timing: one reciprocal bit per clock, from the 2**0 term down to the lowest set bit of ``r``:
the unit stops as soon as the remaining bits are all zero, so ``cycles(k)`` depends on k
(k = 1 and other powers of two are fastest).  See ``cycles``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numba import njit

from model.units import fixed, rom


@dataclass(frozen=True)
class DividerConfig:
    """Widths of the shift-add divider.

    The default serves scan lines up to 2047 pixels (``k_width`` = 11).  ``recip_bits`` = 20 is
    chosen so that every k gets a useful reciprocal *and* the increment it makes stays good over a
    whole line: ``|k*r - 2**N| <= k/2``, so a Gouraud increment ``dI = (I_b - I_a)/k`` accumulated
    over the k pixels of the line drifts from the exact end value by at most
    ``|I_b - I_a| * k / 2**(N+1) <= 255 * 2047 / 2**21 = 0.25`` of an 8-bit level.  N = 19 would
    give 0.498 levels (no margin); N = 11 (just enough for r >= 1) drifts by up to 85 levels.

    ``a_width`` = 21 holds the difference of two Q8.12 intensities (the Gouraud unit's default
    format): 255 * 2**12 needs 20 bits plus the sign.
    """

    a_width: int = 21
    k_width: int = 11
    recip_bits: int = 20

    def __post_init__(self) -> None:
        fixed.check_width("a_width", self.a_width, 2, 40)
        fixed.check_width("k_width", self.k_width, 1, 16)
        fixed.check_width("recip_bits", self.recip_bits, 1, 40)
        if self.q_width > fixed.MAX_KERNEL_WIDTH:
            raise ValueError(
                f"a_width + recip_bits = {self.q_width} is out of range: the quotient must fit "
                f"in {fixed.MAX_KERNEL_WIDTH} bits"
            )
        if self.k_width > self.recip_bits + 1:
            # round(2**N / k) is 0 for every k > 2**(N+1): such a k would divide to 0.
            raise ValueError(
                f"k_width = {self.k_width} is out of range for recip_bits = {self.recip_bits}: "
                f"round(2**{self.recip_bits} / k) is 0 for k > {2 ** (self.recip_bits + 1)}; "
                f"legal k_width is 1..{self.recip_bits + 1}"
            )

    @property
    def q_width(self) -> int:
        """Quotient width: a_width integer bits (sign included) + recip_bits fraction bits."""
        return self.a_width + self.recip_bits

    @property
    def q_frac_bits(self) -> int:
        return self.recip_bits

    @property
    def recip_width(self) -> int:
        """ROM word width: r = 2**N for k = 1 needs N + 1 bits."""
        return self.recip_bits + 1

    @property
    def rom_bits(self) -> int:
        """The reciprocal ROM: one word per k = 0..2**k_width - 1."""
        return (1 << self.k_width) * self.recip_width

    @property
    def a_range(self) -> tuple[int, int]:
        return fixed.signed_range(self.a_width)

    @property
    def k_max(self) -> int:
        return (1 << self.k_width) - 1

    @property
    def rom_name(self) -> str:
        return f"divider_recip_k{self.k_width}_n{self.recip_bits}.hex"


DEFAULT = DividerConfig()
ARTICLE = DividerConfig(a_width=9, k_width=5, recip_bits=8)
"""The article's case: N = 8 shifts, 9-bit signed differences (+-255), k up to 31."""

# Configurations whose ROM images are committed under rtl/rom (``make roms``); the benches use them.
ROM_CONFIGS: dict[str, DividerConfig] = {
    "default": DEFAULT,
    "article": ARTICLE,
    "n4": DividerConfig(a_width=9, k_width=5, recip_bits=4),
    "n16": DividerConfig(a_width=16, k_width=11, recip_bits=16),
}


def reciprocal(k: int | np.ndarray, recip_bits: int) -> int | np.ndarray:
    """The ROM word ``round(2**recip_bits / k)`` for k >= 1.

    Rounds half up: ``floor(2**N / k + 1/2) = (2**(N+1) + k) // (2k)``.  A tie needs
    2**(N+1) / k to be an odd integer, i.e. k = 2**(N+1) exactly, which rounds up to 1; no k a
    valid configuration accepts (k <= 2**(N+1) - 1) is a tie.  For k > 2**(N+1) the word is 0.
    """
    fixed.check_width("recip_bits", recip_bits, 1, 40)
    karr = fixed.check_operand("k", k, 1, np.iinfo(np.int64).max >> (recip_bits + 2))
    r = ((1 << (recip_bits + 1)) + karr) // (2 * karr)
    return int(r) if r.ndim == 0 else r


def rom_words(cfg: DividerConfig = DEFAULT) -> np.ndarray:
    """The reciprocal ROM, one word per k = 0..2**k_width - 1 (the k = 0 word is 0, unused)."""
    words = np.zeros(1 << cfg.k_width, dtype=np.int64)
    words[1:] = reciprocal(np.arange(1, 1 << cfg.k_width), cfg.recip_bits)
    return words


def rom_layout(cfg: DividerConfig = DEFAULT) -> rom.RomLayout:
    """The ROM image of ``cfg``: 2**k_width words of recip_width bits, for K_WIDTH, RECIP_BITS."""
    config = (("K_WIDTH", cfg.k_width), ("RECIP_BITS", cfg.recip_bits))
    return rom.RomLayout("divider_recip", 1 << cfg.k_width, cfg.recip_width, config)


def rom_text(cfg: DividerConfig = DEFAULT) -> str:
    header = (
        f"divider_shift reciprocal ROM: round(2^{cfg.recip_bits} / k) for k = 0..{cfg.k_max}\n"
        f"{cfg.recip_width}-bit words; k = 0 holds 0 (div_zero). Generated by model.divider."
    )
    return rom.format_image(rom_words(cfg), rom_layout(cfg), header)


def rom_path(cfg: DividerConfig = DEFAULT):
    return rom.ROM_DIR / cfg.rom_name


def read_rom(cfg: DividerConfig = DEFAULT, path=None) -> list[int]:
    """The data words of the image at ``path`` (default ``rom_path(cfg)``), checked against
    ``cfg`` (``rom.read_hex``: a bad or foreign image raises ``rom.RomFileError``)."""
    return rom.read_hex(rom_path(cfg) if path is None else path, rom_layout(cfg))


def write_roms() -> list:
    """Write the ROM image of every configuration in ``ROM_CONFIGS`` to rtl/rom/."""
    paths = []
    for cfg in ROM_CONFIGS.values():
        path = rom_path(cfg)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(rom_text(cfg))
        paths.append(path)
    return paths


def _checked(a, k, cfg: DividerConfig) -> tuple[np.ndarray, np.ndarray]:
    a_lo, a_hi = cfg.a_range
    a_arr = fixed.check_operand("a", a, a_lo, a_hi)
    # k = 0 is legal input to the unit (it raises div_zero), but not to a Python division.
    k_arr = fixed.check_operand("k", k, 1, cfg.k_max)
    return np.broadcast_arrays(a_arr, k_arr)


@njit(cache=True)
def _shift_add_kernel(a: np.ndarray, recip: np.ndarray, recip_bits: int, q: np.ndarray) -> None:
    """The datapath of the article's fig. 3, one reciprocal bit per step, MSB (2**0 term) first."""
    for i in range(a.size):
        shift_reg = a[i] << recip_bits  # the dividend with N extra fraction bits
        acc = 0
        for j in range(recip_bits + 1):
            if (recip[i] >> (recip_bits - j)) & 1:
                acc += shift_reg  # add where i_j = 1 ...
            shift_reg >>= 1  # ... and shift in every step (exact: N spare fraction bits)
        q[i] = acc


def divide(a, k, cfg: DividerConfig = DEFAULT):
    """The bit-exact quotient of the unit: ``a * round(2**N / k)``, in units of 2**-N.

    ``a`` and ``k`` broadcast like numpy arrays; scalars give an int.  The fraction bits of the
    result are ``cfg.q_frac_bits`` (= N): the real quotient is ``divide(a, k) / 2**N``.
    Raises ``ValueError`` for k = 0 (the RTL flags it with ``div_zero``) and any operand outside
    its format.
    """
    a_arr, k_arr = _checked(a, k, cfg)
    recip = _rom_and_cycles(cfg)[0][k_arr.ravel()]
    q = np.empty(a_arr.size, dtype=np.int64)
    _shift_add_kernel(np.ascontiguousarray(a_arr.ravel()), recip, cfg.recip_bits, q)
    q = q.reshape(a_arr.shape)
    return int(q) if q.ndim == 0 else q


def divide_many(a, k, cfg: DividerConfig = DEFAULT) -> tuple[np.ndarray, np.ndarray]:
    """Many divisions in one call: (quotients, busy cycles), element i equal to
    ``divide(a[i], k[i], cfg)`` and ``cycles(k[i], cfg)``.

    ``a`` and ``k`` are integer arrays of one shape (empty allowed; no broadcasting), checked
    once for the batch; both results have that shape, int64.  A bad operand raises the
    ``ValueError`` of ``divide``, naming the element: ``k[3] = 0 is out of range``.
    """
    if np.shape(a) != np.shape(k) or np.ndim(a) == 0:
        raise ValueError(
            f"operand shapes are out of range: got a {np.shape(a)}, k {np.shape(k)}; legal are "
            "arrays of one shape"
        )
    a_lo, a_hi = cfg.a_range
    a_arr = fixed.check_operand("a", a, a_lo, a_hi, rows=True)
    k_arr = fixed.check_operand("k", k, 1, cfg.k_max, rows=True)
    words, cycles_per_k = _rom_and_cycles(cfg)
    q = np.empty(a_arr.size, dtype=np.int64)
    _shift_add_kernel(a_arr.ravel(), words[k_arr.ravel()], cfg.recip_bits, q)
    return q.reshape(a_arr.shape), cycles_per_k[k_arr]


@functools.cache
def _rom_and_cycles(cfg: DividerConfig) -> tuple[np.ndarray, np.ndarray]:
    """The ROM words and ``cycles`` of every k of ``cfg``, computed once (read-only)."""
    words = rom_words(cfg)
    cycles_per_k = _cycles_for_words(words, cfg.recip_bits)
    words.flags.writeable = cycles_per_k.flags.writeable = False
    return words, cycles_per_k


@njit(cache=True)
def _restoring_kernel(a: np.ndarray, k: np.ndarray, q_width: int, frac_bits: int, q: np.ndarray):
    """Restoring division of |a| * 2**N by k, one quotient bit per step, sign applied after."""
    for i in range(a.size):
        dividend = abs(a[i]) << frac_bits
        rem = 0
        quot = 0
        for bit in range(q_width - 1, -1, -1):
            rem = (rem << 1) | ((dividend >> bit) & 1)
            quot <<= 1
            if rem >= k[i]:  # trial subtraction succeeds: keep it
                rem -= k[i]
                quot |= 1
        q[i] = -quot if a[i] < 0 else quot


def divide_exact(a, k, cfg: DividerConfig = DEFAULT):
    """An exact (restoring) divider for comparison: a / k truncated toward zero to N fraction bits.

    Same formats as ``divide``; it takes ``cycles_exact(cfg)`` clocks whatever k is.
    """
    a_arr, k_arr = _checked(a, k, cfg)
    q = np.empty(a_arr.size, dtype=np.int64)
    _restoring_kernel(
        np.ascontiguousarray(a_arr.ravel()),
        np.ascontiguousarray(k_arr.ravel()),
        cfg.q_width,
        cfg.recip_bits,
        q,
    )
    q = q.reshape(a_arr.shape)
    return int(q) if q.ndim == 0 else q


def cycles(k, cfg: DividerConfig = DEFAULT):
    """Clock cycles ``busy`` stays high for one division by k (k = 0 included: 1 cycle).

    One cycle per reciprocal bit from the 2**0 term down to the lowest set bit of r, so
    ``N + 1 - ctz(r)``.  ``valid`` comes in the first cycle after them, together with busy = 0,
    and a new start is accepted in that cycle: one division every ``cycles(k) + 1`` clocks.
    """
    k_arr = fixed.check_operand("k", k, 0, cfg.k_max)
    c = _rom_and_cycles(cfg)[1][k_arr]
    return int(c) if c.ndim == 0 else c


def _cycles_for_words(words: np.ndarray, recip_bits: int) -> np.ndarray:
    """N + 1 - ctz(r) per ROM word; a zero word (k = 0) takes a single cycle."""
    low_bit = words & -words
    ctz = np.where(words > 0, np.log2(np.maximum(low_bit, 1)).astype(np.int64), 0)
    return np.where(words > 0, recip_bits + 1 - ctz, 1)


def cycles_exact(cfg: DividerConfig = DEFAULT) -> int:
    """Clock cycles of the restoring divider: one per quotient bit."""
    return cfg.q_width


def reciprocal_terms(k: int, recip_bits: int) -> list[int]:
    """The exponents j of the terms 1/2**j that make up ``reciprocal(k, recip_bits)``."""
    r = reciprocal(k, recip_bits)
    return [j for j in range(recip_bits + 1) if (r >> (recip_bits - j)) & 1]


@dataclass(frozen=True)
class TradeRow:
    """Accuracy and cost of one reciprocal width over a divisor range."""

    recip_bits: int
    worst_abs_error: float  # quotient units, for the given dividend
    worst_abs_k: int
    worst_rel_error: float  # fraction of the exact quotient
    worst_rel_k: int
    useless_k: int  # divisors whose reciprocal rounds to 0
    cycles_max: int
    cycles_mean: float


def trade_row(recip_bits: int, k_max: int, dividend: int = 255) -> TradeRow:
    """Measure the divider for one N over k = 1..k_max with the given dividend (float errors).

    Computed from ``reciprocal`` directly, so N too small for k_max is measured, not refused.
    """
    ks = np.arange(1, k_max + 1)
    r = reciprocal(ks, recip_bits)
    approx = dividend * r / 2.0**recip_bits
    exact = dividend / ks
    abs_err = np.abs(approx - exact)
    rel_err = abs_err / np.abs(exact)
    cyc = _cycles_for_words(r, recip_bits)
    return TradeRow(
        recip_bits=recip_bits,
        worst_abs_error=float(abs_err.max()),
        worst_abs_k=int(ks[abs_err.argmax()]),
        worst_rel_error=float(rel_err.max()),
        worst_rel_k=int(ks[rel_err.argmax()]),
        useless_k=int((r == 0).sum()),
        cycles_max=int(cyc.max()),
        cycles_mean=float(cyc.mean()),
    )


# ==================================================================== accuracy (worst cases)
def article_table1(recip_bits: int = 8, dividend: int = 255) -> tuple[np.ndarray, np.ndarray]:
    """Table 1 of the article recomputed for every one of its k = 2..16: (error, relative
    error) of ``dividend * round(2**N / k) / 2**N`` against ``dividend / k``, each computed as
    an exact fraction and then rounded to the nearest float."""
    err, rel = [], []
    for k in range(2, 17):
        e = Fraction(dividend * reciprocal(k, recip_bits), 2**recip_bits) - Fraction(dividend, k)
        err.append(float(e))
        rel.append(float(e / Fraction(dividend, k)))
    return np.array(err), np.array(rel)


def line_drift(recip_bits: int, k_max: int, span: float = 255.0) -> tuple[float, int]:
    """The worst drift, in levels, of a line's end value when the exact quotient span / k is
    accumulated over the k steps of the line, over every k = 1..k_max, and the k reaching it.

    The quotient is ``a * r / 2**N`` exactly (no bit lost), so k of them add up to
    ``a * k * r / 2**N``, off the end value a by ``|a| * |k r - 2**N| / 2**N``: linear in |a|,
    so the largest span is the worst dividend, and the maximum over every k is exhaustive.
    ``|k r - 2**N| <= k / 2`` bounds it by ``span * k_max / 2**(N+1)``.
    """
    ks = np.arange(1, k_max + 1)
    off = np.abs(ks * reciprocal(ks, recip_bits) - (1 << recip_bits)) / 2.0**recip_bits
    i = int(np.argmax(off))
    return float(span * off[i]), int(ks[i])
