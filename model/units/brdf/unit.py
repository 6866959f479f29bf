# SPDX-License-Identifier: Apache-2.0
"""BRDF family: the hardware unit's line, as ``rtl/brdf_unit.v`` computes it (docs/brdf_unit.md).

The unit shares the patent specular unit's front and protocol: operand registers c, dz, z0, n,
len (the formats of ``FixedConfig.angle``, a ``SpecularConfig``), the accumulator
zeta(i) = z0 + i dz (``angle.acc_width`` bits, never wraps), per pixel the form's output word
``fixed.evaluate(cfg, zeta, n)`` (``out_bits`` fraction bits), times C rounded (add half, slice)
and saturated to ``angle.out_width`` bits, as the specular unit's multiplier 13 does with its
ROM-12 word.  n outside 1..1000 gives intensity 0 and n_err = 1 on every pixel.

Owns which forms have RTL (``RTL_FORMS``: every form of the family, ``FORM_LATENCY``) and the
extra rules a unit's tables impose (``check_unit``), ``unit_line``, the timing
(``form_latency``, ``fill_latency``, ``cycles``, ``valid_offsets``), ``hdl_parameters`` and the
ROM images (``rom_layout``, ``rom_text``,
``rom_path``, ``read_rom``, ``write_roms``: the angle table, the coefficient table of a form
that has one, the log2 form's second table; ``UNIT_CONFIGS`` names the committed ones).  Only
``c_int_bits``, ``c_frac_bits``, ``z_int_bits``, ``z_frac_bits``, ``len_width`` and
``out_width`` of ``cfg.angle`` reach the unit; its n range is always 1..1000.  May import numpy,
numba, ``model.units.fixed``, ``rom``, ``model.units.specular``'s public names and ``fixed``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numba import njit

from model.units import fixed as fx
from model.units import rom
from model.units.brdf.fixed import (
    COSINE_QUADRATIC,
    CUBIC,
    FORMS,
    LOG2,
    PIECEWISE,
    QUADRATIC,
    FixedConfig,
    angle_table,
    coefficient_words,
    evaluate,
    log2_table,
)
from model.units.specular import N_MAX, N_WIDTH

ANGLE_FIELDS = ("c_int_bits", "c_frac_bits", "z_int_bits", "z_frac_bits", "len_width", "out_width")
"""The fields of ``FixedConfig.angle`` that reach the unit (each an RTL parameter); the rest of
that ``SpecularConfig`` changes nothing here."""
FRONT_STAGES = 7
"""Clock edges of every form's front and back: the accumulator, |zeta| in two steps, the
angle-table address, the table read, the w gate (w = 2**D from pi/2 on), and x C; the
rounded, saturated result is registered at the next edge (docs/brdf_unit.md, "Timing")."""
FORM_LATENCY: dict[str, int] = {
    "cosine_quadratic": 5,
    "quadratic": 6,
    "cubic": 13,
    "log2": 7,
    "piecewise": 24,
}
"""Pipeline stages of each form's datapath module (rtl/brdf_<form>.v), w in to the output word,
at the form's default widths (``UNIT_CONFIGS``): a constant of the form but for the piecewise
form, whose divider takes one stage per quotient bit (``form_latency``: out_bits + 8, 24 at
out_bits = 16)."""
RTL_FORMS = tuple(FORM_LATENCY)
"""The forms with RTL: every form of the family (``fixed.FORMS``)."""
QUADRATIC_A_INT_BITS = 10
"""Integer bits of the quadratic's coefficient a: its largest value, 786.44 at n = 1000, needs
10 (``FixedConfig.coef_formats`` gives the same for every coef_bits from 10 on, which the tests
check; the RTL derives a's fraction bits as COEF_BITS - 10 and the ROM image's header carries
the model's, so a disagreement stops the simulation)."""
CUBIC_R_INT_BITS = 11
"""Integer bits of the cubic's coefficient r = 1/(1 - s): its largest value, 1443.2 at n = 1000,
needs 11 (``coef_formats`` gives r Q11, p0 Q1, b1 and b2 Q0 for every coef_bits from 11 on,
which the tests check; the RTL derives the four fraction widths from COEF_BITS and the image's
header carries the model's)."""
CUBIC_COEF_WORDS = 2
"""Image words per n of the cubic's coefficient table: {r, p0} at 2 (n - 1), {b1, b2} at
2 (n - 1) + 1, each 2 coef_bits wide (the ROM module rtl/shading_rom.v holds words of 64 bits
at most; the unit reads both in one clock through the ROM's two ports)."""
PIECEWISE_COEF_WORDS = 2
"""Image words per n of the piecewise form's coefficient table, three coefficients a word:
{r, p0, b1} at 2 (n - 1), {b2, s2, beta} at 2 (n - 1) + 1, each 3 coef_bits wide, read in one
clock through the ROM's two ports (as the cubic's two words are)."""
PIECEWISE_COEF_BITS_MAX = 21
"""The piecewise form's widest coefficient word: three a ROM word of at most 64 bits
(rtl/shading_rom.v).  Its formats are the cubic's r Q11, p0 Q1, b1 and b2 Q0, then s2 = 2 s and
beta = 2 (n - 1)(1 - s) in Q1 (below 2 and 1.39), for every coef_bits from 11 on (tested)."""
PIECEWISE_MIN_LATENCY = 14
"""The piecewise datapath's fewest stages: the cubic's 13 (its instance) and the select."""
UNIT_CONFIGS: dict[str, FixedConfig] = {
    "cosine_quadratic": COSINE_QUADRATIC,
    "quadratic": QUADRATIC,
    "cubic": CUBIC,
    "log2": LOG2,
    "piecewise": PIECEWISE,
}
"""The configurations whose ROM images are committed under rtl/rom/ (``make roms``) and which
the bench runs: each form's default widths (``fixed.CONFIGS``)."""


def check_unit(cfg: FixedConfig) -> FixedConfig:
    """``cfg`` if the unit can be built for it, else ``ValueError`` naming the field, its value
    and the legal range: the quadratic's coefficient word must hold a up to 786.44
    (coef_bits >= 10; ``FixedConfig`` alone allows 4), the cubic's r up to 1443.2
    (coef_bits >= 11; ``FixedConfig`` refuses the cubic's products wider than 62 bits:
    work_bits above 25, coef_bits + work_bits above 56), and the piecewise form's the same r
    with three coefficients a ROM word of 64 bits (coef_bits 11..21; ``FixedConfig`` refuses its
    work_bits above 25)."""
    if not isinstance(cfg, FixedConfig):
        raise ValueError(f"cfg = {cfg!r} is out of range: legal is a FixedConfig")
    if cfg.form == "quadratic":
        fx.check_width("coef_bits", cfg.coef_bits, QUADRATIC_A_INT_BITS, 32)
    if cfg.form == "cubic":
        fx.check_width("coef_bits", cfg.coef_bits, CUBIC_R_INT_BITS, 32)
    if cfg.form == "piecewise":
        fx.check_width("coef_bits", cfg.coef_bits, CUBIC_R_INT_BITS, PIECEWISE_COEF_BITS_MAX)
    return cfg


def form_latency(cfg: FixedConfig) -> int:
    """Pipeline stages of the form's datapath module (``FORM_LATENCY``); the piecewise form's:
    the bloom part's 6 stages to the divider (the product r w in two, its rounding, beta (r w - 1)
    in two, the denominator), one stage per quotient bit (out_bits + 1: ``rtl/brdf_div.v``) and
    the select, out_bits + 8, but at least the cubic's 13 and the select
    (``PIECEWISE_MIN_LATENCY``)."""
    if check_unit(cfg).form == "piecewise":
        return max(PIECEWISE_MIN_LATENCY, cfg.out_bits + 8)
    return FORM_LATENCY[cfg.form]


def fill_latency(cfg: FixedConfig) -> int:
    """Clock edges from an accepted start to the first valid: ``FRONT_STAGES`` + the form's."""
    return FRONT_STAGES + form_latency(cfg)


# ==================================================================== the line
@njit(cache=True)
def _accumulate(dz: int, z0: int, out: np.ndarray) -> None:
    """The accumulator: out[i] = z0 + i dz (exact: ``acc_width`` bits never wrap)."""
    value = z0
    for i in range(out.size):
        out[i] = value
        value += dz


@njit(cache=True)
def scale_kernel(words: np.ndarray, c: int, shift: int, out_max: int, out: np.ndarray) -> None:
    """Per pixel: the form's output word x C, rounded (add half, slice) and saturated."""
    for i in range(words.size):
        out[i] = fx.saturate(fx.round_shift(c * words[i], shift), 0, out_max)


def _check_line(c, dz, z0, n, length, cfg: FixedConfig) -> tuple[int, int, int, int, int]:
    acc = check_unit(cfg).angle
    c_i = int(fx.check_operand("c", c, 0, acc.c_format.hi))
    z_lo, z_hi = acc.z_format.lo, acc.z_format.hi
    dz_i = int(fx.check_operand("dz", dz, z_lo, z_hi))
    z0_i = int(fx.check_operand("z0", z0, z_lo, z_hi))
    n_i = int(fx.check_operand("n", n, 0, (1 << N_WIDTH) - 1))
    len_i = int(fx.check_operand("length", length, 0, acc.len_max))
    return c_i, dz_i, z0_i, n_i, len_i


def line_angles(dz, z0, length, cfg: FixedConfig) -> np.ndarray:
    """The accumulator zeta(i) = z0 + i dz for each of the l + 1 pixels."""
    _, dz_i, z0_i, _, len_i = _check_line(0, dz, z0, 1, length, cfg)
    acc = np.empty(len_i + 1, dtype=np.int64)
    _accumulate(dz_i, z0_i, acc)
    return acc


def unit_line(c, dz, z0, n, length, cfg: FixedConfig) -> tuple[np.ndarray, int]:
    """What ``rtl/brdf_unit.v`` outputs for one line: (the l + 1 intensities, n_err).

    ``c``: the C register (unsigned Q(c_int_bits).(c_frac_bits) of ``cfg.angle``, output LSBs);
    ``dz``, ``z0``: signed Q(z_int_bits).(z_frac_bits), units of pi/2; ``n``: any 10-bit value
    (1..1000 are the unit's, every other gives zeros with n_err = 1); ``length``: the intervals
    l, 0..2**len_width - 1.  Pixel i is ``evaluate(cfg, z0 + i dz, n)`` x C, rounded (add half,
    slice: c_frac_bits + out_bits bits dropped) and saturated to ``angle.out_width`` bits.
    Raises ``ValueError`` naming a bad operand, its value and the legal range.
    """
    c_i, dz_i, z0_i, n_i, len_i = _check_line(c, dz, z0, n, length, cfg)
    if not 1 <= n_i <= N_MAX:
        return np.zeros(len_i + 1, dtype=np.int64), 1
    acc = np.empty(len_i + 1, dtype=np.int64)
    _accumulate(dz_i, z0_i, acc)
    words = evaluate(cfg, acc, n_i)
    out = np.empty(len_i + 1, dtype=np.int64)
    a = cfg.angle
    scale_kernel(words, c_i, a.c_frac_bits + cfg.out_bits, a.out_max, out)
    return out, 0


def cycles(length, cfg: FixedConfig):
    """Clock cycles ``busy`` is high for a line of l intervals: ``fill_latency(cfg)`` + l.

    The l + 1 valid strobes come at ``valid_offsets``; the last in the first cycle busy is 0,
    when a new start is already accepted.  Takes an int or an array of interval counts."""
    c = fill_latency(cfg) + fx.check_operand("length", length, 0, cfg.angle.len_max)
    return int(c) if c.ndim == 0 else c


def valid_offsets(length, cfg: FixedConfig) -> list[int]:
    """Cycle offsets of the valid strobes (0 = the cycle right after the start edge)."""
    len_i = int(fx.check_operand("length", length, 0, cfg.angle.len_max))
    first = fill_latency(cfg)
    return list(range(first, first + len_i + 1))


# ==================================================================== ROM images
WHICH = ("angle", "coef", "log2")


def _check_which(cfg: FixedConfig, which: str) -> None:
    if which not in WHICH:
        raise ValueError(f"which = {which!r} is out of range: legal are {WHICH}")
    if (which == "coef" and not cfg.coefficients) or (which == "log2" and cfg.form != "log2"):
        raise ValueError(
            f"which = {which!r} is out of range: the {cfg.form} form has no such table"
        )


def rom_name(cfg: FixedConfig, which: str) -> str:
    """The image's file name: the angle table by what it holds (w = 1 - cos, shared by every
    form but log2) and its widths, ``brdf_w_a12_d20.hex``; the coefficient table by form,
    word width and its coefficients' formats, ``brdf_quadratic_coef_c18_q10.8.hex``,
    ``brdf_cubic_coef_c18_q11.7_q1.17_q0.18_q0.18.hex``,
    ``brdf_piecewise_coef_c18_q11.7_q1.17_q0.18_q0.18_q1.17_q1.17.hex``; the log2 form's angle table
    ``brdf_log2cos_a12_d20.hex`` and its second table by its widths, ``brdf_log2_a10_d16.hex``."""
    _check_which(cfg, which)
    if which == "angle":
        kind = "log2cos" if cfg.form == "log2" else "w"
        return f"brdf_{kind}_a{cfg.cos_addr_bits}_d{cfg.cos_data_bits}.hex"
    if which == "log2":
        return f"brdf_log2_a{cfg.log_addr_bits}_d{cfg.log_data_bits}.hex"
    fmt = "_".join(f"q{q.int_bits}.{q.frac_bits}" for q in cfg.coef_formats.values())
    return f"brdf_{cfg.form}_coef_c{cfg.coef_bits}_{fmt}.hex"


def rom_path(cfg: FixedConfig, which: str = "angle") -> Path:
    """The committed image of the angle table (``which="angle"``), the coefficient table
    (``"coef"``) or the log2 form's second table (``"log2"``) under rtl/rom/."""
    return rom.ROM_DIR / rom_name(check_unit(cfg), which)


def _coef_frac_bits(cfg: FixedConfig) -> int:
    return next(iter(cfg.coef_formats.values())).frac_bits


def rom_layout(cfg: FixedConfig, which: str = "angle") -> rom.RomLayout:
    """The image of the angle table (2**A words of D bits; fields COS_ADDR_BITS,
    COS_DATA_BITS, TABLE) or of the coefficient table: the quadratic's 1000 words of coef_bits,
    a of n at address n - 1 (fields FORM, COEF_BITS, COEF_FRAC_BITS); the cubic's 2000 words of
    2 coef_bits (``CUBIC_COEF_WORDS``; fields FORM, COEF_BITS and each coefficient's fraction
    bits, R_FRAC_BITS, P0_FRAC_BITS, B1_FRAC_BITS, B2_FRAC_BITS); the piecewise form's 2000
    words of 3 coef_bits (``PIECEWISE_COEF_WORDS``; fields FORM, COEF_BITS and the six fraction
    widths, the cubic's four, S2_FRAC_BITS, BETA_FRAC_BITS); or the log2 form's second table,
    2**log_addr_bits words of log_data_bits (fields LOG_ADDR_BITS, LOG_DATA_BITS)."""
    check_unit(cfg)
    _check_which(cfg, which)
    if which == "log2":
        config = (("LOG_ADDR_BITS", cfg.log_addr_bits), ("LOG_DATA_BITS", cfg.log_data_bits))
        return rom.RomLayout("brdf_log2", 1 << cfg.log_addr_bits, cfg.log_data_bits, config)
    if which == "angle":
        config = (
            ("COS_ADDR_BITS", cfg.cos_addr_bits),
            ("COS_DATA_BITS", cfg.cos_data_bits),
            ("TABLE", rom.TABLE_NAMES.index("log2cos" if cfg.form == "log2" else "w")),
        )
        return rom.RomLayout("brdf_angle", 1 << cfg.cos_addr_bits, cfg.cos_data_bits, config)
    if cfg.form in ("cubic", "piecewise"):
        fracs = tuple(
            (f"{name.upper()}_FRAC_BITS", q.frac_bits) for name, q in cfg.coef_formats.items()
        )
        config = (("FORM", FORMS.index(cfg.form)), ("COEF_BITS", cfg.coef_bits), *fracs)
        words = CUBIC_COEF_WORDS if cfg.form == "cubic" else PIECEWISE_COEF_WORDS
        width = len(cfg.coefficients) // words * cfg.coef_bits
        return rom.RomLayout(f"brdf_{cfg.form}_coef", words * N_MAX, width, config)
    config = (
        ("FORM", FORMS.index(cfg.form)),
        ("COEF_BITS", cfg.coef_bits),
        ("COEF_FRAC_BITS", _coef_frac_bits(cfg)),
    )
    return rom.RomLayout("brdf_coef", N_MAX, cfg.coef_bits, config)


def rom_words(cfg: FixedConfig, which: str = "angle") -> np.ndarray:
    """The data words of the image: ``angle_table``, the quadratic's coefficient column, the
    cubic's coefficients two to a word (r above p0, then b1 above b2, for each n), the piecewise
    form's three to a word ({r, p0, b1}, then {b2, s2, beta}, the first named in the highest
    bits), or ``log2_table``."""
    check_unit(cfg)
    _check_which(cfg, which)
    if which == "angle":
        return angle_table(cfg)
    if which == "log2":
        return log2_table(cfg)
    words = coefficient_words(cfg)
    if cfg.form in ("cubic", "piecewise"):
        # each n's coefficients in order, cut into its image words, the first in the high bits
        count = CUBIC_COEF_WORDS if cfg.form == "cubic" else PIECEWISE_COEF_WORDS
        per_word = len(cfg.coefficients) // count
        packed = np.zeros((N_MAX, len(cfg.coefficients) // per_word), dtype=np.int64)
        for j in range(len(cfg.coefficients)):
            shift = cfg.coef_bits * (per_word - 1 - j % per_word)
            packed[:, j // per_word] |= words[:, j] << shift
        return packed.reshape(-1)
    return words[:, 0]


def rom_text(cfg: FixedConfig, which: str = "angle") -> str:
    """The ``$readmemh`` image of the angle or the coefficient table."""
    layout = rom_layout(cfg, which)
    if which == "angle" and cfg.form == "log2":
        header = (
            f"brdf_unit angle table, log2 form: -log2 cos(i/2^{cfg.cos_addr_bits} * pi/2) as "
            f"round(-log2(cos x) 2^{cfg.cos_data_bits - 2}), saturated to "
            f"2^{cfg.cos_data_bits} - 1, i < 2^{cfg.cos_addr_bits}\n"
            "the log2 form reads it. Generated by model.units.brdf."
        )
    elif which == "log2":
        header = (
            f"brdf_unit log2 table: log2(1 + j/2^{cfg.log_addr_bits}) as round(log2(1 + f) "
            f"2^{cfg.log_data_bits}), j < 2^{cfg.log_addr_bits}\n"
            "the log2 form's second table (the log2 device). Generated by model.units.brdf."
        )
    elif which == "angle":
        header = (
            f"brdf_unit angle table: w = 1 - cos(i/2^{cfg.cos_addr_bits} * pi/2) as "
            f"round(2 sin^2(x/2) 2^{cfg.cos_data_bits}), i < 2^{cfg.cos_addr_bits}\n"
            "every form but log2 reads it. Generated by model.units.brdf."
        )
    elif cfg.form == "cubic":
        fmts = ", ".join(
            f"{name} Q{q.int_bits}.{q.frac_bits}" for name, q in cfg.coef_formats.items()
        )
        header = (
            f"brdf_unit coefficient table, cubic form: for n = 1..{N_MAX}, r above p0 at "
            f"address 2 (n - 1), b1 above b2 at 2 (n - 1) + 1\n"
            f"each unsigned, {cfg.coef_bits} bits: {fmts}. Generated by model.units.brdf."
        )
    elif cfg.form == "piecewise":
        fmts = ", ".join(
            f"{name} Q{q.int_bits}.{q.frac_bits}" for name, q in cfg.coef_formats.items()
        )
        header = (
            f"brdf_unit coefficient table, piecewise form: for n = 1..{N_MAX}, r, p0, b1 (high to "
            f"low bits) at address 2 (n - 1), b2, s2, beta at 2 (n - 1) + 1\n"
            f"each unsigned, {cfg.coef_bits} bits: {fmts}. Generated by model.units.brdf."
        )
    else:
        q = next(iter(cfg.coef_formats.values()))
        header = (
            f"brdf_unit coefficient table, {cfg.form} form: a(n) for n = 1..{N_MAX} at "
            f"address n - 1, unsigned Q{q.int_bits}.{q.frac_bits}\n"
            "Generated by model.units.brdf."
        )
    return rom.format_image(rom_words(cfg, which), layout, header)


def read_rom(cfg: FixedConfig, which: str = "angle", path=None) -> list[int]:
    """The data words of the image at ``path`` (default ``rom_path(cfg, which)``), checked
    against ``cfg`` (``rom.read_hex``: a bad or foreign image raises ``rom.RomFileError``)."""
    path = rom_path(cfg, which) if path is None else path
    return rom.read_hex(path, rom_layout(cfg, which))


def rom_kinds(cfg: FixedConfig) -> tuple[str, ...]:
    """The tables the unit of ``cfg`` reads: ``("angle",)``, and ``"coef"`` if it has one,
    ``"log2"`` for the log2 form."""
    check_unit(cfg)
    if cfg.coefficients:
        return ("angle", "coef")
    return ("angle", "log2") if cfg.form == "log2" else ("angle",)


def write_roms() -> list[Path]:
    """Write the images of every configuration in ``UNIT_CONFIGS`` to rtl/rom/."""
    paths = []
    for cfg in UNIT_CONFIGS.values():
        for which in rom_kinds(cfg):
            path = rom_path(cfg, which)
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(rom_text(cfg, which))
            paths.append(path)
    return list(dict.fromkeys(paths))


# ==================================================================== RTL parameters
def hdl_parameters(cfg: FixedConfig) -> dict[str, object]:
    """The Verilog parameters of ``rtl/brdf_unit.v`` for ``cfg`` (its fields in UPPER_CASE,
    the angle format's six fields, the ROM images as absolute paths; COEF_ROM_FILE only for a
    form with a coefficient table, LOG_ROM_FILE only for the log2 form)."""
    check_unit(cfg)
    a = cfg.angle
    params: dict[str, object] = {
        "FORM": cfg.form,
        "C_INT_BITS": a.c_int_bits,
        "C_FRAC_BITS": a.c_frac_bits,
        "Z_INT_BITS": a.z_int_bits,
        "Z_FRAC_BITS": a.z_frac_bits,
        "LEN_WIDTH": a.len_width,
        "OUT_WIDTH": a.out_width,
        "COS_ADDR_BITS": cfg.cos_addr_bits,
        "COS_DATA_BITS": cfg.cos_data_bits,
        "COEF_BITS": cfg.coef_bits,
        "WORK_BITS": cfg.work_bits,
        "OUT_BITS": cfg.out_bits,
        "LOG_ADDR_BITS": cfg.log_addr_bits,
        "LOG_DATA_BITS": cfg.log_data_bits,
        "ANGLE_ROM_FILE": str(rom_path(cfg, "angle")),
    }
    if cfg.coefficients:
        params["COEF_ROM_FILE"] = str(rom_path(cfg, "coef"))
    if cfg.form == "log2":
        params["LOG_ROM_FILE"] = str(rom_path(cfg, "log2"))
    return params
