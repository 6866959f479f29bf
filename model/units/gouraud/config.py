# SPDX-License-Identifier: Apache-2.0
"""Segment Gouraud unit: configuration (widths, segment size P) and the default unit.

Owns ``LANE_COUNTS`` (the P the unit accepts), ``GouraudConfig`` with its formats and the
internal widths that mirror the RTL's localparams, and ``DEFAULT``.  May import
``model.units.fixed`` and ``network`` (a configuration knows its increment network).
"""

from __future__ import annotations

from dataclasses import dataclass

from model.units import fixed
from model.units.gouraud.network import IncrementNetwork, increment_network, log2_exact

LANE_COUNTS = (2, 4, 8, 16)  # P the unit (model and RTL) accepts


@dataclass(frozen=True)
class GouraudConfig:
    """Widths and segment size of the segment Gouraud unit.

    The default serves 8-bit intensities on scan lines up to 2047 pixels (``len_width`` = 11),
    8 pixels a clock (the article's choice, P = 8).  ``i_frac`` = 12: the host quantises the
    increment to the nearest 2**-12, an error of at most 2**-13 per pixel, which accumulated
    over the 2046 steps of a 2047-pixel line stays within 2046 / 2**13 = 0.2498 of an output
    level (``drift_bound``; reached: ``drift_worst``); 11 fraction bits would give
    1023 / 2**11 = 0.4996, no margin before a rounding flip.  The difference of two Q8.12
    intensities is 21 bits signed: the shift-add divider's default dividend width
    (``divider.DEFAULT.a_width``), and exactly ``di``'s format.
    """

    i_int: int = 8
    i_frac: int = 12
    p: int = 8
    len_width: int = 11

    def __post_init__(self) -> None:
        fixed.check_width("i_int", self.i_int, 1, 16)
        fixed.check_width("i_frac", self.i_frac, 1, 24)
        log2_exact(self.p, "p", LANE_COUNTS[-1])
        # Lines must be able to span more than one segment (else no start register is needed);
        # this also keeps every RTL slice and sign extension at least one bit wide.
        fixed.check_width("len_width", self.len_width, self.log2_p + 1, 16)

    # ---------------------------------------------------------------- formats
    @property
    def i_width(self) -> int:
        """Width of ``i0``: unsigned Q(i_int).(i_frac)."""
        return self.i_int + self.i_frac

    @property
    def di_width(self) -> int:
        """Width of ``di``: signed Q(i_int+1).(i_frac), sign included."""
        return self.i_int + 1 + self.i_frac

    @property
    def i0_format(self) -> fixed.QFormat:
        return fixed.QFormat(self.i_int, self.i_frac, signed=False)

    @property
    def di_format(self) -> fixed.QFormat:
        return fixed.QFormat(self.i_int + 1, self.i_frac, signed=True)

    @property
    def i0_range(self) -> tuple[int, int]:
        return fixed.unsigned_range(self.i_width)

    @property
    def di_range(self) -> tuple[int, int]:
        return fixed.signed_range(self.di_width)

    @property
    def len_max(self) -> int:
        return (1 << self.len_width) - 1

    @property
    def out_max(self) -> int:
        """Largest output pixel: 2**i_int - 1."""
        return (1 << self.i_int) - 1

    @property
    def pixels_width(self) -> int:
        """Width of the packed ``pixels`` port: P lanes of ``i_int`` bits."""
        return self.p * self.i_int

    @property
    def log2_p(self) -> int:
        return self.p.bit_length() - 1

    @property
    def round_bias(self) -> int:
        """2**(i_frac-1): added once to the start register so that every lane truncates."""
        return 1 << (self.i_frac - 1)

    # ---------------------------------------------------------------- internal widths
    @property
    def inc_width(self) -> int:
        """Signed width of the increment network's multiples i*dI, i <= P (no wrap)."""
        return self.di_width + self.log2_p

    @property
    def acc_width(self) -> int:
        """Signed width of the start register and the lane adders: nothing legal wraps.

        The largest multiplier ever formed is M = 2**len_width: the next start after the last
        segment of the longest line (ceil(len_max / P) * P = 2**len_width, as len_width > log2 P).
        The extremes are therefore ``lo = bias - M * 2**W`` (i0 = 0, di most negative) and
        ``hi = (2**W - 1) + bias + M * (2**W - 1)`` (both largest), W = i_width,
        bias = 2**(i_frac-1).  ``lo`` needs len_width + W + 1 bits; so does ``hi`` exactly when
        ``2**W + bias <= M``, i.e. W < len_width; otherwise one bit more (the default: 33 bits).
        The RTL computes the same ``localparam ACC_WIDTH``; tests/test_gouraud.py checks that the
        width is the minimal one and that the extreme inputs reach both ends.
        """
        return self.len_width + self.i_width + 1 + (1 if self.i_width >= self.len_width else 0)

    @property
    def network(self) -> IncrementNetwork:
        return increment_network(self.p)


DEFAULT = GouraudConfig()
