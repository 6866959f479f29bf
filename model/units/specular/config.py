# SPDX-License-Identifier: Apache-2.0
"""Specular unit: configuration (formats, table choice, the a(n) mapping), named configurations.

Owns the unit's constants (``N_WIDTH``, ``N_MAX``, ``FILL_LATENCY``, the k ranges), the float
scale ``alpha_value`` and ``epicentre`` it is derived from, ``SpecularConfig`` with its derived
widths and RTL parameters, ``a_words`` (ROM 9's contents: ``mag_int_bits`` needs its smallest
word), ``rom_path`` (``hdl_parameters`` names the ROM files) and ``DEFAULT``, ``PROTOTYPE``,
``INFLECTION``, ``NARROW``, ``KEPT``, ``UP5K``, ``ROM_CONFIGS``, ``KEPT_CONFIGS``.  May import
numpy and ``model.units.fixed`` and ``rom`` only: every other module of the package builds on
this one.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from model.units import fixed, rom

N_WIDTH = 10
"""Width of the n register and of the decoder: n = 1..1000 needs 10 bits (the patent says 9)."""
N_MAX = 1000
FILL_LATENCY = 8
"""Clock edges from an accepted start to the first valid: acc, |acc| in two steps, x a, address,
ROM 12, zero gate, x C, round (docs/specular.md, "Timing")."""
MAX_TABLES = 4
ALPHA_MODES = ("taylor", "inflection")

PATENT_K_RANGES = ((1, 1, 1), (2, 2, 2), (3, 6, 4), (7, 1000, 16))
"""The patent's mapping (fig. 13): (n_lo, n_hi, k) -> k = 1, 2, 4, 16."""
PROTOTYPE_K_RANGES = ((1, 1000, 2),)
"""The prototype (Abbas, Szirmay-Kalos, Horvath 2000): cos^2 only, a = sqrt(n/2)."""


# ==================================================================== the scale a(n)
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


def _n_k_pairs(ranges) -> list[tuple[int, int]]:
    return [(n, k) for lo, hi, k in ranges for n in range(lo, hi + 1)]


# ==================================================================== configuration
def _kept_pairs(cfg: SpecularConfig) -> list[tuple[int, int]]:
    """(n, k) of every n the unit keeps (n_first..n_last)."""
    return [(n, k) for n, k in _n_k_pairs(cfg.k_ranges) if cfg.n_first <= n <= cfg.n_last]


def a_words(cfg: SpecularConfig) -> np.ndarray:
    """round(alpha_value(n, k) * 2**a_frac_bits) indexed by the 10-bit n, 0 for every n the unit
    refuses (0, n < n_first, n > n_last, > 1000); ROM 9 holds words n_first..n_last of it
    (``roms.rom9_words`` is the public call; this one also serves ``mag_int_bits_for``)."""
    words = np.zeros(1 << N_WIDTH, dtype=np.int64)
    for n, k in _kept_pairs(cfg):
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
    n_first: int = 1  # the kept range of n: ROM 9 holds a for n_first..n_last only, every
    n_last: int = N_MAX  # other n gives what an invalid n gives (zeros, n_err = 1)

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
        for name, lo in (("n_first", 1), ("n_last", self.n_first)):
            value = getattr(self, name)
            if not isinstance(value, int | np.integer) or not lo <= value <= N_MAX:
                first = " (n_first..1000)" if name == "n_last" else ""
                raise ValueError(
                    f"{name} = {value!r} is out of range: legal is {lo}..{N_MAX}{first}"
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
        a_max = max(alpha_value(n, k, self.alpha) for n, k in _kept_pairs(self))
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
    def rom9_depth(self) -> int:
        """ROM 9's words: one per kept n (n_first..n_last), at address n - n_first."""
        return self.n_last - self.n_first + 1

    @property
    def rom9_bits(self) -> int:
        """ROM 9: one a word for every kept n."""
        return self.rom9_depth * self.a_width

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

        The smallest M such that the clamped value times the smallest a of any kept n
        (n_first..n_last) still reaches pi/2 (cos^k = 0): clamping then never changes a result,
        it only narrows the multiplier.  Capped at the accumulator's own integer bits.  Only the
        kept range counts: a dropped n never reaches multiplier 11 with a result (its pixels are
        gated to 0), so a range without the small n (a grows with n) narrows the multiplier;
        the RTL's ``a_extreme`` scans the same range, and the largest a (``a_int_bits``'s check)
        is also taken over the kept range.
        """
        return mag_int_bits_for(self)

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
        kept = f"_keep{self.n_first}-{self.n_last}" if self.rom9_depth < N_MAX else ""
        return (
            f"specular_a_{self.alpha}_{self.rom_tag}_q{self.a_int_bits}.{self.a_frac_bits}"
            f"{kept}.hex"
        )

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
            "N_FIRST": self.n_first,
            "N_LAST": self.n_last,
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
def mag_int_bits_for(cfg: SpecularConfig) -> int:
    """``SpecularConfig.mag_int_bits`` of ``cfg`` (cached per configuration; needs only the
    k ranges and formats, so it also answers for a configuration built without its checks)."""
    a_min = int(a_words(cfg)[cfg.n_first : cfg.n_last + 1].min())
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
KEPT = replace(NARROW, n_first=17, n_last=40)
"""NARROW keeping n = 17..40 only (24 ROM-9 words) for the bench of the kept range: the
smallest kept a is sqrt(17/16) > 1, so ``mag_int_bits`` is 0 (NARROW's is 1)."""
UP5K = SpecularConfig(rom_addr_bits=11, rom_data_bits=12)
"""The patent's four tables, 2^11 x 12 bits each, so that ROM 9 and ROM 12 fit the 30 block RAMs
(RAM40, 4 kbit) of a Lattice iCE40 UP5K (docs/specular.md, "Fitting an iCE40 UP5K")."""

# Configurations whose ROM images are committed under rtl/rom (``make roms``); the benches use them.
ROM_CONFIGS: dict[str, SpecularConfig] = {
    "default": DEFAULT,
    "narrow": NARROW,
    "prototype": PROTOTYPE,
    "inflection": INFLECTION,
    "up5k": UP5K,
}
KEPT_CONFIGS: dict[str, SpecularConfig] = {"kept": KEPT}
"""Configurations that keep only a range of n: their images are committed too (``make roms``)
and the bench runs them, but they are not in ``ROM_CONFIGS``, whose accuracy walk and tables
cover every n = 1..1000."""


def rom_path(cfg: SpecularConfig = DEFAULT, which: str = "a") -> Path:
    """The committed image of ROM 9 (``which="a"``) or ROM 12 (``"cos"``) under rtl/rom/."""
    if which not in ("a", "cos"):
        raise ValueError(f"which = {which!r} is out of range: legal are 'a', 'cos'")
    return rom.ROM_DIR / (cfg.a_rom_name if which == "a" else cfg.cos_rom_name)
