# SPDX-License-Identifier: Apache-2.0
"""Segment Gouraud unit: the bit-exact datapath, per line, per segment and for a batch of lines.

Owns the numba kernels of the article's figs. 3 and 4 (segment adders, output conversion), the
operand checks, ``segment_values``, ``segments``, ``shade_line``, the port views
(``pack_pixels``, ``pack_mask``, ``unit_results``), the timing (``cycles``,
``valid_offsets``), the drift figures and ``shade_lines``: many lines (and colour channels) in
one call, every row equal to its ``shade_line``, for the renderer.  May import numpy, numba,
``model.units.fixed`` and ``batch``, and ``config`` and ``network``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from model.units import batch, fixed
from model.units.gouraud.config import DEFAULT, GouraudConfig
from model.units.gouraud.network import network_arrays


# ------------------------------------------------------------------------------------------------
# The datapath
# ------------------------------------------------------------------------------------------------
@njit(cache=True)
def _segment_kernel(
    start0: int,
    di: int,
    shift_w: np.ndarray,
    add_t: np.ndarray,
    add_a: np.ndarray,
    add_b: np.ndarray,
    add_sub: np.ndarray,
    values: np.ndarray,
    mult: np.ndarray,
) -> None:
    """The article's figs. 3 and 4: multiples from shifts and adders, P lane adders per segment,
    and the next start I0 + P*dI carried in the start register.  ``mult`` (P + 1 words) is
    scratch space for the multiples i*dI (the caller's, so a batch allocates it once)."""
    p = values.shape[1]
    mult[:] = 0
    for k in range(shift_w.size):  # wired shifts 2**w * dI
        mult[1 << shift_w[k]] = di << shift_w[k]
    for k in range(add_t.size):  # the network's adders, in level order
        if add_sub[k]:
            mult[add_t[k]] = mult[add_a[k]] - mult[add_b[k]]
        else:
            mult[add_t[k]] = mult[add_a[k]] + mult[add_b[k]]
    start = start0
    for s in range(values.shape[0]):
        for j in range(p):
            values[s, j] = start + mult[j]
        start = start + mult[p]  # the start register's next value


@njit(cache=True)
def _convert_kernel(values: np.ndarray, frac: int, hi: int, out: np.ndarray) -> None:
    """Per lane: drop the fraction bits (the bias made it a rounding), clamp to 0..hi."""
    for s in range(values.shape[0]):
        for j in range(values.shape[1]):
            out[s, j] = fixed.saturate(fixed.trunc_shift(values[s, j], frac), 0, hi)


def _check_line(i0, di, length, cfg: GouraudConfig, min_length: int) -> tuple[int, int, int]:
    """The three operands of one line as ints, or ``ValueError`` naming the bad one."""
    checked = []
    for name, value, (lo, hi) in (
        ("i0", i0, cfg.i0_range),
        ("di", di, cfg.di_range),
        ("length", length, (min_length, cfg.len_max)),
    ):
        arr = fixed.check_operand(name, value, lo, hi)
        if arr.ndim != 0:
            raise ValueError(f"{name} must be a single integer (one line), got shape {arr.shape}")
        checked.append(int(arr))
    return checked[0], checked[1], checked[2]


def segment_count(length: int, p: int) -> int:
    """Segments the unit emits for a line: ceil(length / P), and 1 (empty) for length 0."""
    return max(1, -(-length // p))


def _values(i0: int, di: int, length: int, cfg: GouraudConfig) -> np.ndarray:
    values = np.empty((segment_count(length, cfg.p), cfg.p), dtype=np.int64)
    mult = np.empty(cfg.p + 1, dtype=np.int64)
    _segment_kernel(i0 + cfg.round_bias, di, *network_arrays(cfg.network), values, mult)
    return values


def _mask(length: int, cfg: GouraudConfig) -> np.ndarray:
    nseg = segment_count(length, cfg.p)
    return np.arange(nseg * cfg.p).reshape(nseg, cfg.p) < length


def segment_values(i0, di, length, cfg: GouraudConfig = DEFAULT) -> np.ndarray:
    """The lane adders' outputs per segment, shape (segments, P), signed ``acc_width`` values.

    They include the rounding bias: lane i of segment s holds
    ``i0 + 2**(i_frac-1) + (s*P + i)*di`` (all lanes of the last segment, masked or not).
    """
    return _values(*_check_line(i0, di, length, cfg, 1), cfg)


class Segments(NamedTuple):
    """What the unit emits for a line: per segment the P output pixels and the lane mask."""

    pixels: np.ndarray  # (segments, P) int64, 0..2**i_int - 1, lane 0 = leftmost
    mask: np.ndarray  # (segments, P) bool, True = the lane belongs to the line


def _segments(i0: int, di: int, length: int, cfg: GouraudConfig) -> Segments:
    values = _values(i0, di, length, cfg)
    pixels = np.empty_like(values)
    _convert_kernel(values, cfg.i_frac, cfg.out_max, pixels)
    return Segments(pixels, _mask(length, cfg))


def segments(i0, di, length, cfg: GouraudConfig = DEFAULT) -> Segments:
    """Per segment the P lane intensities (rounded, saturated) and the mask, as the RTL emits.

    ``i0`` unsigned Q(i_int).(i_frac), ``di`` signed Q(i_int+1).(i_frac), ``length`` 1..len_max
    pixels.  The last segment's lanes past the line end are computed like the others (the RTL
    outputs them) and masked off.
    """
    return _segments(*_check_line(i0, di, length, cfg, 1), cfg)


def shade_line(i0, di, length, cfg: GouraudConfig = DEFAULT) -> np.ndarray:
    """The line's ``length`` output pixels, left to right (the masked lanes of ``segments``)."""
    seg = segments(i0, di, length, cfg)
    return seg.pixels[seg.mask]


def pack_pixels(lanes, cfg: GouraudConfig = DEFAULT) -> int:
    """The ``pixels`` port word: lane 0 in the low ``i_int`` bits (a Python int, any width)."""
    word = 0
    for j, v in enumerate(np.asarray(lanes).tolist()):
        word |= int(v) << (j * cfg.i_int)
    return word


def pack_mask(mask) -> int:
    """The ``mask`` port word: bit j = lane j."""
    return sum(1 << j for j, m in enumerate(np.asarray(mask).tolist()) if m)


# ------------------------------------------------------------------------------------------------
# The RTL's view: cycles and per-valid outputs, length 0 included
# ------------------------------------------------------------------------------------------------
def cycles(length, cfg: GouraudConfig = DEFAULT):
    """Clock cycles ``busy`` is high for a line: ceil(length / P), 1 for length 0.

    ``valid`` follows one cycle behind (``valid_offsets``); the last segment comes out with
    busy = 0, and a new start is accepted in that cycle: one line every ``cycles + 1`` clocks.
    Takes an int or an array of lengths (then returns an array).
    """
    arr = fixed.check_operand("length", length, 0, cfg.len_max)
    c = np.maximum(1, -(-arr // cfg.p))  # segment_count, vectorised
    return int(c) if c.ndim == 0 else c


def valid_offsets(length: int, cfg: GouraudConfig = DEFAULT) -> list[int]:
    """Cycles (0 = the one right after the edge that accepted start) with ``valid`` = 1."""
    return list(range(1, cycles(length, cfg) + 1))


def unit_results(i0, di, length, cfg: GouraudConfig = DEFAULT) -> list[dict[str, int]]:
    """The output ports at each ``valid``: packed ``pixels``, ``mask`` bits and ``last``.

    Accepts length 0 (the RTL's empty segment: mask 0, last 1, the lanes computed as usual).
    """
    seg = _segments(*_check_line(i0, di, length, cfg, 0), cfg)
    n = seg.pixels.shape[0]
    return [
        {
            "pixels": pack_pixels(seg.pixels[s], cfg),
            "mask": pack_mask(seg.mask[s]),
            "last": int(s == n - 1),
        }
        for s in range(n)
    ]


def drift_bound(cfg: GouraudConfig = DEFAULT) -> float:
    """Worst drift, in output levels, of a rounded increment accumulated over the longest line:
    (len_max - 1) steps of at most 2**-(i_frac+1) each."""
    return (cfg.len_max - 1) / 2.0 ** (cfg.i_frac + 1)


def drift_worst(cfg: GouraudConfig = DEFAULT) -> float:
    """The exact worst drift, in output levels, of a rounded increment over the longest line.

    A line of m pixels from I_a to I_b (Q``i_int``.``i_frac``, so D = I_b - I_a is an integer
    number of 2**-i_frac) has m - 1 steps; the host rounds D / (m - 1) to the nearest integer q,
    and the end pixel's value I_a + (m - 1) q misses I_b by |(m - 1) q - D|, the distance of D
    to the nearest multiple of m - 1: at most floor((m - 1) / 2), reached by D = floor((m - 1)
    / 2) itself.  The longest line is the worst: floor((len_max - 1) / 2)
    * 2**-i_frac levels (``drift_bound``'s (len_max - 1) / 2**(i_frac+1) when len_max - 1 is
    even, as for 2047 pixels).
    """
    return ((cfg.len_max - 1) // 2) / 2.0**cfg.i_frac


# ------------------------------------------------------------------------------------------------
# Many lines at once
# ------------------------------------------------------------------------------------------------
@njit(cache=True)
def line_kernel(
    i0: int,
    di: int,
    length: int,
    bias: int,
    frac: int,
    out_max: int,
    shift_w: np.ndarray,
    add_t: np.ndarray,
    add_a: np.ndarray,
    add_b: np.ndarray,
    add_sub: np.ndarray,
    values_buf: np.ndarray,
    lanes_buf: np.ndarray,
    mult: np.ndarray,
    out: np.ndarray,
) -> None:
    """One line of ``length`` pixels (checked operands), as ``shade_line``, into ``out[:length]``:
    the kernel ``shade_lines`` runs per line and channel, public for fused renderers.
    ``values_buf``, ``lanes_buf`` ((>= ceil(length / P), P) int64) and ``mult`` (P + 1) are the
    caller's scratch space; the network arrays are ``network_arrays(cfg.network)``."""
    p = values_buf.shape[1]
    nseg = (length + p - 1) // p
    values = values_buf[:nseg]
    lanes = lanes_buf[:nseg]
    _segment_kernel(i0 + bias, di, shift_w, add_t, add_a, add_b, add_sub, values, mult)
    _convert_kernel(values, frac, out_max, lanes)
    for x in range(length):
        out[x] = lanes[x // p, x % p]


def shade_lines(i0, di, length, cfg: GouraudConfig = DEFAULT, out=None, at=None) -> batch.LineBatch:
    """``shade_line`` for L lines in one call: row j of the result equals
    ``shade_line(i0[j], di[j], length[j], cfg)``.

    ``i0`` and ``di`` are (L,) integer arrays, or (L, C) for C colour channels that share a
    line's length (each channel is then one run of the unit); ``length`` (L,) pixels per line,
    1..len_max as for ``shade_line``; L = 0 is allowed.  Returns a ``batch.LineBatch`` whose
    ``pixels`` are the lines' pixels one after the other, (sum of length,) or (sum, C), and
    whose ``cycles`` are ``cycles(length[j])`` per line (per channel).  With ``out`` (int64,
    (N,) or (N, C)) and ``at`` ((L,) rows) line j is written to ``out[at[j] : at[j] +
    length[j]]`` instead and ``pixels`` is ``out``.  A bad operand raises the ``ValueError`` of
    ``shade_line``, naming the row: ``di[3, 1] = ... is out of range``.

    The pixels come from ``lane_pixel``, the lane adders' closed form, not from the segment
    network ``shade_line`` models: the network's multiples are exact (``acc_width`` holds every
    legal value), so both are ``i0 + bias + x * dI`` truncated and saturated, and the batched
    call runs several times faster (tests/test_gouraud.py and tests/test_batch.py compare every
    row with ``shade_line``).
    """
    batch.check_rows({"i0": i0, "di": di, "length": length}, channels=("i0", "di"))
    i0_a = fixed.check_operand("i0", i0, *cfg.i0_range, rows=True)
    di_a = fixed.check_operand("di", di, *cfg.di_range, rows=True)
    len_a = fixed.check_operand("length", length, 1, cfg.len_max, rows=True)
    channels = None if i0_a.ndim == 1 else i0_a.shape[1]
    pixels, starts, offsets = batch.place_lines(len_a, out, at, channels)
    _lines_closed_kernel(
        i0_a.reshape(len_a.size, channels or 1),
        di_a.reshape(len_a.size, channels or 1),
        len_a,
        starts,
        cfg.round_bias,
        cfg.i_frac,
        cfg.out_max,
        pixels[:, None] if channels is None else pixels,  # a view: writes reach ``out``
    )
    return batch.LineBatch(pixels=pixels, offsets=offsets, cycles=np.maximum(1, -(-len_a // cfg.p)))


@njit(cache=True, inline="always")
def lane_pixel(i0: int, di: int, x: int, bias: int, frac: int, out_max: int) -> int:
    """Pixel x of a line (checked operands) in closed form: the lane adder holds ``i0 + bias
    + x * di`` exactly (the increment network's multiples are exact, ``mult[j] = j * dI``, and
    the start register advances by ``mult[P] = P * dI``), then the output conversion.  The
    same pixels as ``shade_line`` for every configuration (``tests/test_fast_pipeline.py``
    compares them), without the per-segment network: the renderer's fast path."""
    return fixed.saturate(fixed.trunc_shift(i0 + bias + x * di, frac), 0, out_max)


@njit(cache=True)
def _lines_closed_kernel(
    i0: np.ndarray,
    di: np.ndarray,
    length: np.ndarray,
    starts: np.ndarray,
    bias: int,
    frac: int,
    out_max: int,
    out: np.ndarray,
) -> None:
    """``shade_lines``: line j, channel c in closed form into ``out[starts[j] + x, c]``."""
    for j in range(length.size):
        for c in range(i0.shape[1]):
            base = starts[j]
            for x in range(length[j]):
                out[base + x, c] = lane_pixel(i0[j, c], di[j, c], x, bias, frac, out_max)


@njit(cache=True)
def line_closed_kernel(
    i0: int, di: int, length: int, bias: int, frac: int, out_max: int, out: np.ndarray
) -> None:
    """``line_kernel`` in closed form (``lane_pixel`` for x = 0..length-1) into ``out``."""
    for x in range(length):
        out[x] = lane_pixel(i0, di, x, bias, frac, out_max)
