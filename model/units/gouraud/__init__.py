# SPDX-License-Identifier: Apache-2.0
"""Segment Gouraud unit (Romanyuk, docs/gouraud.md): P pixels of a scan line per clock.

Along a scan line the intensity grows by a constant increment: ``I(x) = I0 + x*dI``.  The unit
computes a whole *segment* of P pixels at once, ``I0 + i*dI`` for i = 0..P-1, with no
multiplier: the multiples ``i*dI`` come from hard-wired shifts ``2**w * dI`` and a few adders
(the *increment network*, derived from P by ``increment_network``), and P segment adders make
the lanes and ``I0 + P*dI``, the first pixel of the next segment, which goes back into the start
register.  The last segment of a line may stick out past its end: a mask marks the lanes that
belong to the line.

Formats (``GouraudConfig``; integers in units of 2**-f, f = ``i_frac``):
* ``i0`` start intensity: unsigned Q``i_int``.``i_frac`` (default Q8.12, 0 .. 256 - 2**-12);
* ``di`` increment: signed Q``i_int+1``.``i_frac`` (the integer bits include the sign; default
  Q9.12: a one-pixel step may be anything from -256 to +256 - 2**-12, which covers +-255);
* ``length``: pixels in the line, unsigned ``len_width`` bits, 1 .. 2**len_width - 1;
* each output pixel: unsigned ``i_int`` bits (0..255), see *Output conversion*;
* internal lane values and the start register: signed ``acc_width`` bits (see
  ``GouraudConfig.acc_width``): no legal input can make them wrap.

Output conversion: round to nearest, ties up (``fixed.round_shift``), then saturate to
0 .. 2**i_int - 1 (``fixed.saturate``).  The hardware does the rounding without a per-lane
adder: the start register is loaded with ``i0 + 2**(f-1)`` (the *rounding bias*, one adder at
start), so every lane only drops its f fraction bits (``fixed.trunc_shift``, wires) and
clamps.  ``trunc(i0 + bias + i*dI) = round(i0 + i*dI)``; the model takes the same two steps.
Saturation matters: an increment from the shift-add divider is approximate and may overshoot
the line's end value (255 + a fraction, or a little below 0); it must clamp, never wrap.

Timing (``cycles``, ``valid_offsets``): ``busy`` is high for one cycle per segment,
``ceil(length / P)``; segment s comes out (``valid``) s + 1 cycles after the start was accepted,
the last one together with ``busy`` = 0 and ``last`` = 1, so a line takes ``ceil(length/P) + 1``
clocks from start to start.  Length 0 (a zero written to the RTL's length register) gives one
*empty* segment: one ``valid`` with ``mask`` = 0 and ``last`` = 1 after one busy cycle, so every
accepted start ends with exactly one ``last``.  The Python line API (``segments``,
``shade_line``) refuses length 0; ``unit_results``/``cycles``/``valid_offsets`` describe the RTL
and accept it.

Modules, each importing only those above it: ``network`` (the increment network derived from
P), ``config`` (formats and widths), ``datapath`` (the bit-exact unit, per line and batched).
This file only re-exports: code outside the package imports ``model.units.gouraud``.
"""

from model.units.gouraud.config import DEFAULT, LANE_COUNTS, GouraudConfig
from model.units.gouraud.datapath import (
    Segments,
    cycles,
    drift_bound,
    drift_worst,
    lane_pixel,
    pack_mask,
    pack_pixels,
    segment_count,
    segment_values,
    segments,
    shade_line,
    shade_lines,
    unit_results,
    valid_offsets,
)
from model.units.gouraud.network import (
    NETWORK_MAX_P,
    Adder,
    IncrementNetwork,
    adder_counts,
    format_network_table,
    increment_count,
    increment_network,
)

__all__ = [
    "DEFAULT",
    "LANE_COUNTS",
    "NETWORK_MAX_P",
    "Adder",
    "GouraudConfig",
    "IncrementNetwork",
    "Segments",
    "adder_counts",
    "cycles",
    "drift_bound",
    "drift_worst",
    "format_network_table",
    "increment_count",
    "increment_network",
    "lane_pixel",
    "pack_mask",
    "pack_pixels",
    "segment_count",
    "segment_values",
    "segments",
    "shade_line",
    "shade_lines",
    "unit_results",
    "valid_offsets",
]
