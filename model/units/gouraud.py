"""Segment Gouraud unit (Romanyuk, SEEDS.md section 2): P pixels of a scan line per clock.

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
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import NamedTuple

import numpy as np
from numba import njit

from model.units import fixed

LANE_COUNTS = (2, 4, 8, 16)  # P the unit (model and RTL) accepts
NETWORK_MAX_P = 64  # increment_count / increment_network enumerate up to this segment size


def _log2_exact(p: int, name: str, hi: int) -> int:
    if not isinstance(p, int | np.integer) or p < 2 or p > hi or p & (p - 1):
        powers = ", ".join(str(1 << w) for w in range(1, hi.bit_length()))
        raise ValueError(f"{name} = {p!r} is out of range: legal values are {powers}")
    return int(p).bit_length() - 1


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
        _log2_exact(self.p, "p", LANE_COUNTS[-1])
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


# ------------------------------------------------------------------------------------------------
# The increment network
# ------------------------------------------------------------------------------------------------
class Adder(NamedTuple):
    """One adder of the increment network: ``target*dI = a*dI +- b*dI``."""

    target: int
    a: int
    b: int
    subtract: bool
    level: int

    def describe(self) -> str:
        return f"{self.target}dI = {self.a}dI {'-' if self.subtract else '+'} {self.b}dI"


@dataclass(frozen=True)
class IncrementNetwork:
    """How the multiples i*dI, i = 1..P, are made: wired shifts and adders, level by level."""

    p: int
    shifts: tuple[int, ...]  # the multiples that are plain wired shifts 2**w (w = 0..log2 P)
    adders: tuple[Adder, ...]  # in level order: an adder only uses shifts and earlier levels

    @property
    def adder_count(self) -> int:
        return len(self.adders)

    @property
    def levels(self) -> int:
        """Adders in series on the longest path (0 when every multiple is a wired shift)."""
        return max((a.level for a in self.adders), default=0)

    def per_level(self) -> list[int]:
        return [sum(1 for a in self.adders if a.level == lv) for lv in range(1, self.levels + 1)]


@cache
def increment_network(p: int) -> IncrementNetwork:
    """Derive the increment network for segment size p (a power of two up to 64).

    Level 0 are the wired shifts ``2**w * dI``, w = 0..log2 p (P*dI included: the next start
    needs it).  Every other multiple i = 1..p gets the lowest level L at which it is
    ``x + y`` or ``x - y`` of two multiples of levels below L; among those, an addition is
    preferred, then the smallest second operand y (and x >= y for an addition).  For p = 8 this
    gives exactly the article's four adders 3 = 2+1, 5 = 4+1, 6 = 4+2, 7 = 8-1 (the one
    subtraction, in two's complement); p = 16 needs a second level for 11 = 10+1 and 13 = 12+1.
    The RTL's constant functions (rtl/gouraud_segment.v) make the same choice.
    """
    log2p = _log2_exact(p, "p", NETWORK_MAX_P)
    shifts = tuple(1 << w for w in range(log2p + 1))
    known = dict.fromkeys(shifts, 0)  # multiple -> level
    need = [i for i in range(1, p + 1) if i not in known]
    adders: list[Adder] = []
    level = 0
    while need:
        level += 1
        below = sorted(known)  # everything of a level < this one
        found: dict[int, Adder] = {}
        for i in need:
            choice = None
            for y in below:  # an addition x + y, x >= y
                if i - y >= y and (i - y) in known:
                    choice = Adder(i, i - y, y, False, level)
                    break
            if choice is None:
                for y in below:  # a subtraction x - y, x <= p
                    if (i + y) in known:
                        choice = Adder(i, i + y, y, True, level)
                        break
            if choice is not None:
                found[i] = choice
        for i, adder in found.items():
            known[i] = level
            adders.append(adder)
        need = [i for i in need if i not in found]
    return IncrementNetwork(p=p, shifts=shifts, adders=tuple(adders))


def increment_count(p: int) -> int:
    """How many of the p increments i*dI (i = 0..p-1) one add or subtract of two shifted
    operands 2**w*dI (w = 0..log2 p) reaches: the article's table, by enumeration.

    Both operands may be the same shift (0 = x - x, 2**(w+1) = 2**w + 2**w), so the plain
    shifts count too.  p = 2, 4, 8, 16, 32, 64 give 2, 4, 8, 14, 22, 32.
    """
    log2p = _log2_exact(p, "p", NETWORK_MAX_P)
    ops = [1 << w for w in range(log2p + 1)]
    reach = {x + y for x in ops for y in ops} | {x - y for x in ops for y in ops}
    return sum(1 for i in range(p) if i in reach)


def adder_counts(p: int) -> dict[str, int]:
    """The unit's adders for segment size p: network, segment block, rounding bias."""
    net = increment_network(p)
    return {
        "network": net.adder_count,
        "network_levels": net.levels,
        # lanes 1..P-1 (lane 0 is the start register itself) + the next start I0 + P*dI
        "segment": p,
        "bias": 1,
        "total": net.adder_count + p + 1,
    }


def format_network_table(ps: tuple[int, ...] = (2, 4, 8, 16, 32, 64)) -> str:
    """Markdown table of the derived network per P (the README's table)."""
    lines = [
        "| P | increments by one add/sub (article) | network adders | adder levels "
        "| adders per level | segment adders | total adders (+1 bias) |",
        "|---|---|---|---|---|---|---|",
    ]
    for p in ps:
        net = increment_network(p)
        cnt = adder_counts(p)
        per_level = " + ".join(str(n) for n in net.per_level()) or "-"
        lines.append(
            f"| {p} | {increment_count(p)} | {net.adder_count} | {net.levels} | {per_level} "
            f"| {cnt['segment']} | {cnt['total']} |"
        )
    return "\n".join(lines)


def _network_arrays(net: IncrementNetwork) -> tuple[np.ndarray, ...]:
    shift_w = np.array([s.bit_length() - 1 for s in net.shifts], dtype=np.int64)
    tgt = np.array([a.target for a in net.adders], dtype=np.int64)
    opa = np.array([a.a for a in net.adders], dtype=np.int64)
    opb = np.array([a.b for a in net.adders], dtype=np.int64)
    sub = np.array([int(a.subtract) for a in net.adders], dtype=np.int64)
    return shift_w, tgt, opa, opb, sub


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
    _segment_kernel(i0 + cfg.round_bias, di, *_network_arrays(cfg.network), values, mult)
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
