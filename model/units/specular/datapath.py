# SPDX-License-Identifier: Apache-2.0
"""Specular unit: the bit-exact datapath, per line (``shade_line``) and for a batch of lines.

Owns the numba kernels of fig. 1 (accumulate, |acc| x a, ROM 12, x C, round, saturate), the
operand checks, ``line_angles``, ``shade_line``, ``unit_line`` (any 10-bit n, as the RTL), the
timing (``cycles``, ``valid_offsets``) and ``shade_lines``: many lines in one call, every row
equal to its ``shade_line``, for the renderer.  May import numpy, numba, ``model.units.fixed``
and ``batch``, and ``config`` and ``roms``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from model.units import batch, fixed
from model.units.specular.config import DEFAULT, FILL_LATENCY, N_WIDTH, SpecularConfig
from model.units.specular.roms import n_valid, tables


@njit(cache=True)
def _accumulate(dz: int, z0: int, length: int, acc: np.ndarray) -> None:
    """Adder 6 + multiplexer 7 + register 8: acc[0] = z0, acc[i] = acc[i-1] + dz (exact)."""
    value = z0
    for i in range(length + 1):
        if i > 0:
            value += dz
        acc[i] = value


@njit(cache=True, inline="always")
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
def pixels_kernel(
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
        out[i] = pixel_value(
            acc[i], c, a_word, tsel, rom12, mag_max, shift, addr_bits, out_shift, out_max
        )


@njit(cache=True, inline="always")
def pixel_value(
    acc: int,
    c: int,
    a_word: int,
    tsel: int,
    rom12: np.ndarray,
    mag_max: int,
    shift: int,
    addr_bits: int,
    out_shift: int,
    out_max: int,
) -> int:
    """One pixel from its accumulator value (register 8, ``z0 + i * dz``: the adder is
    exact): the ROM-12 word, x C (multiplier 13), round, saturate.  ``pixels_kernel`` per
    pixel, public for fused renderers."""
    word = _rom12_word(acc, a_word, tsel, rom12, mag_max, shift, addr_bits)
    return fixed.saturate(fixed.round_shift(c * word, out_shift), 0, out_max)


@njit(cache=True)
def rom12_path_kernel(
    acc: np.ndarray,
    a_word: int,
    tsel: int,
    rom12: np.ndarray,
    mag_max: int,
    shift: int,
    addr_bits: int,
    out: np.ndarray,
) -> None:
    """The ROM-12 word of every accumulator value (the unit up to multiplier 13): what the
    accuracy tests read the tables through."""
    for i in range(acc.size):
        out[i] = _rom12_word(acc[i], a_word, tsel, rom12, mag_max, shift, addr_bits)


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
    t = tables(cfg)
    acc = np.empty(length + 1, dtype=np.int64)
    _accumulate(dz, z0, length, acc)
    out = np.empty(length + 1, dtype=np.int64)
    pixels_kernel(acc, c, int(t.rom9[n]), int(t.tsel[n]), *t.pixel_args, out)
    return out


def shade_line(c, dz, z0, n, length, cfg: SpecularConfig = DEFAULT) -> np.ndarray:
    """The l+1 output intensities of one line, bit-exact with ``rtl/specular_unit.v``.

    ``c``: C register (unsigned, ``c_frac_bits`` fraction bits, in output LSBs); ``dz``, ``z0``:
    angle registers (signed, units of pi/2 * 2**-z_frac_bits); ``n``: 1..1000 (the kept range
    ``n_first..n_last``); ``length``: the number of intervals l (0..2**len_width - 1).  Raises
    ``ValueError`` for anything outside.
    """
    c_i, dz_i, z0_i, len_i = _check_line(c, dz, z0, length, cfg)
    n_i = int(fixed.check_operand("n", n, cfg.n_first, cfg.n_last))
    return _run_line(c_i, dz_i, z0_i, n_i, len_i, cfg)


def unit_line(c, dz, z0, n, length, cfg: SpecularConfig = DEFAULT) -> tuple[np.ndarray, int]:
    """What the RTL does for any 10-bit n: (intensities, n_err).

    For n = n_first..n_last (by default 1..1000) this is ``(shade_line(...), 0)``; for every
    other n (0, 1001..1023 and the n outside the kept range) the line has the same l+1 results
    at the same cycles, every one 0 with ``n_err`` = 1.
    """
    c_i, dz_i, z0_i, len_i = _check_line(c, dz, z0, length, cfg)
    n_i = int(fixed.check_operand("n", n, 0, (1 << N_WIDTH) - 1))
    if not n_valid(n_i, cfg):
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


# ==================================================================== many lines at once
@njit(cache=True)
def _lines_kernel(
    c: np.ndarray,
    dz: np.ndarray,
    z0: np.ndarray,
    n: np.ndarray,
    length: np.ndarray,
    starts: np.ndarray,
    rom9: np.ndarray,
    tsel: np.ndarray,
    rom12: np.ndarray,
    mag_max: int,
    shift: int,
    addr_bits: int,
    out_shift: int,
    out_max: int,
    out: np.ndarray,
) -> None:
    """``_run_line`` for every row j, its l + 1 pixels written to ``out[starts[j]:]``: the
    accumulator (register 8) of pixel x is ``z0 + x * dz`` exactly (adder 6 is exact), so each
    pixel is ``pixel_value`` of it, with no accumulator buffer."""
    for j in range(c.size):
        a_word, t_sel, base = rom9[n[j]], tsel[n[j]], starts[j]
        for x in range(length[j] + 1):
            out[base + x] = pixel_value(
                z0[j] + x * dz[j], c[j], a_word, t_sel, rom12, mag_max, shift, addr_bits,
                out_shift, out_max,
            )  # fmt: skip


@njit(cache=True)
def line_kernel(
    c: int,
    dz: int,
    z0: int,
    length: int,
    a_word: int,
    tsel: int,
    rom12: np.ndarray,
    mag_max: int,
    shift: int,
    addr_bits: int,
    out_shift: int,
    out_max: int,
    acc_buf: np.ndarray,
    out: np.ndarray,
) -> None:
    """One line of l = ``length`` intervals (checked operands), as ``shade_line``, into
    ``out[:length + 1]``: the kernel ``shade_lines`` runs per line, public for fused renderers.
    ``a_word``, ``tsel`` are ``tables(cfg).rom9[n]``, ``.tsel[n]``; ``acc_buf`` (>= l + 1 int64)
    is the caller's scratch space."""
    acc = acc_buf[: length + 1]
    _accumulate(dz, z0, length, acc)
    pixels_kernel(
        acc, c, a_word, tsel, rom12, mag_max, shift, addr_bits, out_shift, out_max,
        out[: length + 1],
    )  # fmt: skip


def shade_lines(
    c, dz, z0, n, length, cfg: SpecularConfig = DEFAULT, out=None, at=None
) -> batch.LineBatch:
    """``shade_line`` for L lines in one call: row j of the result equals
    ``shade_line(c[j], dz[j], z0[j], n[j], length[j], cfg)``.

    ``c``, ``dz``, ``z0``, ``n``, ``length`` are (L,) integer arrays (L = 0 allowed), ``length``
    the intervals l of each line as in ``shade_line``.  Returns a ``batch.LineBatch`` whose
    ``pixels`` hold the sum of (l + 1) intensities, line after line, and whose ``cycles`` are
    ``FILL_LATENCY + l``.  With ``out`` (an int64 (N,) array) and ``at`` ((L,) rows), line j is
    written to ``out[at[j] : at[j] + l_j + 1]`` instead and ``pixels`` is ``out``.  A bad operand
    raises the ``ValueError`` of ``shade_line``, naming the row: ``c[3] = ... is out of range``.
    """
    batch.check_rows({"c": c, "dz": dz, "z0": z0, "n": n, "length": length})
    z_lo, z_hi = cfg.z_format.lo, cfg.z_format.hi
    c_a = fixed.check_operand("c", c, 0, cfg.c_format.hi, rows=True)
    dz_a = fixed.check_operand("dz", dz, z_lo, z_hi, rows=True)
    z0_a = fixed.check_operand("z0", z0, z_lo, z_hi, rows=True)
    len_a = fixed.check_operand("length", length, 0, cfg.len_max, rows=True)
    n_a = fixed.check_operand("n", n, cfg.n_first, cfg.n_last, rows=True)
    pixels, starts, offsets = batch.place_lines(len_a + 1, out, at, None)
    t = tables(cfg)
    _lines_kernel(c_a, dz_a, z0_a, n_a, len_a, starts, t.rom9, t.tsel, *t.pixel_args, pixels)
    return batch.LineBatch(pixels=pixels, offsets=offsets, cycles=FILL_LATENCY + len_a)
