# SPDX-License-Identifier: Apache-2.0
"""The BRDF unit's own checks in ``make mutants`` (sim/mutation_checks.py lists them last for
each form, in this order): the highlight lines of a form's own highlight and across its marks,
the far lines (the accumulator's bits above the angle's range, each alone), and the exhaustive
check (every n and angle-table address, at the top C and, one pixel at a time, at the C values
that show a change of the output word there), with the piecewise form's one-pixel lines for
64 n.

Size: about 300 lines: each check is a generator of stimulus aimed at one part of the unit,
all of them over the same model of its words (``brdf.evaluate``) and its line protocol.
"""

from __future__ import annotations

import functools
import random
from collections.abc import Callable, Iterator, Sequence

import numpy as np
from numba import njit

from model.units import brdf
from model.units.brdf import FixedConfig
from model.units.brdf.unit import scale_kernel
from model.units.specular import N_MAX
from sim import soak_stimulus, units
from sim.mutation_window import Window

# The highlight lines' seed (the record's lines were drawn with it: sim/mutation_checks.py's
# DIRECTED_SEED + 8)
HIGHLIGHT_SEED = 13


BRDF_HIGHLIGHT = (
    "highlight lines: each inside the lit angles of its n (the form's word at least 1/256) or "
    "across one of its form's marks (where the word leaves full scale, falls below 1/256 or to "
    "0; the cubic's and the piecewise form's tau = 0 and tau = -16, the log2 form's x = 1), C in "
    "its top quarter"
)
BRDF_HIGHLIGHT_JOBS = 3000
# The steepest line across a mark: 2^BRDF_STEEPEST angle LSBs a pixel (4 table addresses at the
# default widths); the shallowest: 1 LSB
BRDF_STEEPEST = 16


@functools.cache
def brdf_marks(cfg: FixedConfig, n: int) -> tuple[int, tuple[int, ...]]:
    """(edge, marks) of the BRDF unit's form for ``n``, as angle-table addresses (``addr_shift``
    angle LSBs each; 2^COS_ADDR_BITS is pi/2): ``edge`` the last address whose output word is
    at least 1/256 of full scale (``brdf.evaluate``), ``marks`` the addresses where the word's
    kind changes (0, below 1/256, lit, full scale: the saturation of the peak, the highlight's
    edge, the zero the log2 form's x = 3 clips to) and where the form's datapath takes another
    branch: the cubic's and the piecewise form's tau = 1 - r w at 0 (the piecewise form's
    junction from the cubic to the bloom part) and at its floor -16, the log2 form's
    x = n (-log2 cos) at 1 (its octave boundary, where u = 1 + x reaches 2), the quadratic's
    1 - a w and the cosine-quadratic's 1 - (7n/16) w at 0 (clipped there), found on the angle
    table from the float coefficients (a line across one meets every rounding point near
    it)."""
    a_bits, o = cfg.cos_addr_bits, cfg.out_bits
    addrs = np.arange((1 << a_bits) + 1, dtype=np.int64)
    word = brdf.evaluate(cfg, addrs << cfg.addr_shift, n)
    full, lit = (1 << o) - 1, 1 << (o - 8) if o > 8 else 1
    kind = np.where(word == 0, 0, np.where(word < lit, 1, np.where(word < full, 2, 3)))
    marks = set(np.nonzero(kind[1:] != kind[:-1])[0] + 1)
    table = brdf.angle_table(cfg)
    d = cfg.cos_data_bits
    if cfg.form == "log2":
        # x = n word >= 2^(D - 2): the second octave (the table word holds D - 2 fraction bits)
        marks.add(int(np.searchsorted(table, (1 << (d - 2)) / n)))
    if cfg.form in ("cubic", "piecewise"):
        r = brdf.coefficient_values(cfg.form, n)[0]
        for tau in (0.0, -16.0):  # w = (1 - tau) / r, D fraction bits
            marks.add(int(np.searchsorted(table, (1.0 - tau) / r * (1 << d))))
    # the quadratic's 1 - a w and the cosine-quadratic's 1 - (7n/16) w clipped at 0 (the word
    # rounds to 0 a few addresses before)
    scale = {"quadratic": lambda: brdf.coefficient_values("quadratic", n)[0],
             "cosine_quadratic": lambda: brdf.cosine_quadratic_scale(n)}.get(cfg.form)  # fmt: skip
    if scale is not None and scale() > 0:
        marks.add(int(np.searchsorted(table, (1 << d) / scale())))
    lit_addrs = np.nonzero(kind >= 2)[0]
    edge = int(lit_addrs.max()) if lit_addrs.size else 0
    return edge, tuple(sorted(int(m) for m in marks if 0 < m <= 1 << a_bits))


def brdf_highlight_inputs(
    cfg: units.UnitConfig, count: int = BRDF_HIGHLIGHT_JOBS
) -> list[dict[str, int]]:
    """Reset, then ``count`` lines of the BRDF unit (the specular unit's highlight
    lines, ``highlight_inputs``, for a form's own highlight), each written, started and waited
    for, n random in 1..1000, C in the top quarter of its range, the angle of either sign:
    half of them inside the lit angles of n (``brdf_marks``' edge; every pixel's output word
    at least 1/256, so a change of one table address, table word or product bit is likely to
    change a result), half across one of n's marks chosen at random (the line's step
    log-uniform from 1 angle LSB to 2^BRDF_STEEPEST, so that it meets the rounding points of
    the angle table's address and of the form's products near it, one address after another,
    or leaps across).  A random soak's lines leave the highlight within a few pixels and
    cross a mark in few of them."""
    assert isinstance(cfg, FixedConfig)
    spec = units.spec(cfg)
    ranges = {p.name: soak_stimulus.port_range(p) for p in spec.operands}
    rng = random.Random(HIGHLIGHT_SEED)
    shift = cfg.addr_shift
    c_lo, c_hi = ranges["c"]
    len_hi = ranges["len"][1]
    z_lo = ranges["z0"][0]
    latency = brdf.fill_latency(cfg)

    def jobs() -> Iterator[dict[str, int]]:
        for k in range(count):
            n = rng.randint(1, 1000)
            edge, marks = brdf_marks(cfg, n)
            length = rng.randint(1, len_hi)
            if k % 2 == 0 or not marks:  # inside the lit angles, as the specular unit's
                top = (edge << shift) + (1 << shift) // 2 - 1  # the edge address's last angle
                z0 = rng.randint(-top, top)
                step = max(1, (top - abs(z0)) // length)
                dz = rng.randint(-step, step)
            else:  # across a mark: the line starts before it and ends after it, either sign
                mark = (rng.choice(marks) << shift) - (1 << shift) // 2  # the rounding point
                dz = max(1, int(2.0 ** rng.uniform(0, BRDF_STEEPEST)))
                z0 = max(mark - rng.randint(1, dz * length), z_lo)
                sign = rng.choice((-1, 1))
                z0, dz = sign * z0, sign * dz
            c = rng.randint(c_hi - (c_hi - c_lo) // 4, c_hi)
            yield dict(c=c, n=n, len=length, z0=z0, dz=dz)

    return soak_stimulus.line_rows(spec, jobs(), lambda job: job["len"] + latency + 4)


# The accumulator's bits above |zeta|'s range: each alone at one pixel of a line (of either sign)
BRDF_FAR = (
    "far lines: lines whose accumulator reaches each of its bits above the angle's range alone, "
    "of either sign, at an angle inside every n's highlight"
)


def brdf_far_inputs(cfg: units.UnitConfig) -> list[dict[str, int]]:
    """Reset, then for each bit b of the BRDF unit's accumulator from the top of z0's range to
    the one below its sign, and each sign, a line that reaches +-(2^b + t) at its pixel
    2^(LEN_WIDTH - 1), t one angle-table address: the accumulator is far beyond pi/2 there
    (every form's word 0), but a "too big" test that misses bit b reads it as t, inside the
    highlight of every n (the word near full scale).  A random soak's accumulator stays near
    z0's range: its lines are short or their steps small."""
    assert isinstance(cfg, FixedConfig)
    spec = units.spec(cfg)
    ranges = {p.name: soak_stimulus.port_range(p) for p in spec.operands}
    z_width = spec.operand("z0").width
    len_width = spec.operand("len").width
    dz_hi = ranges["dz"][1]
    pixel = 1 << (len_width - 1)
    t = 1 << cfg.addr_shift
    latency = brdf.fill_latency(cfg)

    def jobs() -> Iterator[dict[str, int]]:
        for b in range(z_width - 2, z_width + len_width - 1):
            dz = min(1 << max(0, b - (len_width - 1)), dz_hi)
            z0 = (1 << b) + t - pixel * dz
            for sign in (1, -1):
                yield dict(c=ranges["c"][1], n=1 + (b % 7), len=pixel + 1, z0=sign * z0,
                           dz=sign * dz)  # fmt: skip

    return soak_stimulus.line_rows(spec, jobs(), lambda job: job["len"] + latency + 4)


BRDF_EXHAUSTIVE = (
    "every n and angle-table address: each n's lines across every address to pi/2 and beyond "
    "at the top C, then each address whose output word some C shows changed by one, alone, "
    "at a C whose result the word one more changes and at one whose result the word one less "
    "does"
)


# The forms whose exhaustive check has the one-pixel lines: each costs the unit's latency
# (busy for the fill latency + l cycles), 11.9M to 25.1M cycles a form; the piecewise form's
# 4.78 million, at 31 clocks, would be 162M cycles, so its check has the top C's lines alone
# (4.2M) and a check of its own the one-pixel lines for 64 n (``PIXEL_SAMPLE_NS``)
EXHAUSTIVE_PIXELS = ("cosine_quadratic", "quadratic", "cubic", "log2")


@njit(cache=True)
def _sensitive_c(words: int, c_hi: int, shift: int, out_max: int, up, down) -> None:
    """For each output word f < ``words``: ``up[f]``, the largest C at which the result of
    f + 1 (and so of every larger word) differs from f's, ``down[f]`` the largest at which
    f - 1's (and every smaller word's) does; 0 where no C does.  The result is
    round(C f / 2^shift) (add half, slice), saturated to ``out_max``, as ``scale_kernel``."""
    half = 1 << (shift - 1)
    for f in range(words):
        up[f] = 0
        down[f] = 0
        for c in range(c_hi, 0, -1):
            lo = (c * f + half) >> shift
            if up[f] == 0 and f + 1 < words and lo < out_max and (c * f + c + half) >> shift > lo:
                up[f] = c
            if down[f] == 0 and f > 0 and lo <= out_max and (c * f - c + half) >> shift < lo:
                down[f] = c
            if (up[f] != 0 or f + 1 == words) and (down[f] != 0 or f == 0):
                break


@functools.cache
def sensitive_c(cfg: FixedConfig) -> tuple[np.ndarray, np.ndarray]:
    """(up, down) of ``_sensitive_c`` for the BRDF unit ``cfg``'s output words."""
    a = cfg.angle
    words = 1 << cfg.out_bits
    up, down = np.zeros(words, np.int64), np.zeros(words, np.int64)
    _sensitive_c(words, a.c_format.hi, a.c_frac_bits + cfg.out_bits, a.out_max, up, down)
    return up, down


def brdf_exhaustive_jobs(
    cfg: FixedConfig, ns: Sequence[int] | None = None, lines: bool = True,
    pixels: bool | None = None,
) -> np.ndarray:  # fmt: skip
    """The lines of the exhaustive check for each n of ``ns`` (every n of the unit, 1 to
    N_MAX, by default), one row each (c, n, len, z0, dz): first the n's lines from address 0,
    a table address a pixel, to two past pi/2 (the word there is the cos = 0 word, whatever
    the address), C at its top; then, for each address a whose word f some C shows changed
    (``sensitive_c``) and that is not full scale, a one-pixel line at a with C = up[f] and
    one with C = down[f] (``pixels``: by default the forms of ``EXHAUSTIVE_PIXELS``; the top
    C's lines left out with ``lines`` False).  A mutant that changes the
    word of any n at any such address then changes a result: every form's datapath is a
    function of (n, address), pixel by pixel.  A word below about 2^(shift - C's bits) shows
    no change of one at any C (128 at the default widths: C f rounds to 0 whatever C);
    a full-scale word's fall shows at the top C from about 2^(shift - C's bits) down."""
    a_bits, shift = cfg.cos_addr_bits, cfg.addr_shift
    c_hi = cfg.angle.c_format.hi
    len_hi = (1 << cfg.angle.len_width) - 1
    up, down = sensitive_c(cfg)
    full = (1 << cfg.out_bits) - 1
    addrs = np.arange((1 << a_bits) + 1, dtype=np.int64)
    last = (1 << a_bits) + 2
    rows: list[np.ndarray] = []
    if pixels is None:
        pixels = cfg.form in EXHAUSTIVE_PIXELS
    for n in ns if ns is not None else range(1, N_MAX + 1):
        first = 0 if lines else last + 1
        while first <= last:
            length = min(len_hi, last - first)
            rows.append(np.array([[c_hi, n, length, first << shift, 1 << shift]], np.int64))
            first += length + 1
        if not pixels:
            continue
        word = brdf.evaluate(cfg, addrs << shift, n)
        for table in (up, down):
            c = np.where(word < full, table[word], 0)
            at = np.nonzero(c)[0]
            block = np.zeros((at.size, 5), np.int64)
            block[:, 0], block[:, 1], block[:, 3] = c[at], n, addrs[at] << shift
            rows.append(block)
    return np.concatenate(rows)


def _lines_back_to_back(cfg: FixedConfig, jobs: np.ndarray) -> soak_stimulus.Stimulus:
    """``jobs`` (rows of c, n, len, z0, dz) as ``back_to_back`` runs them."""
    spec = units.spec(cfg)
    names = [p.name for p in spec.operands]
    order = [("c", "n", "len", "z0", "dz").index(name) for name in names]
    return soak_stimulus.back_to_back(spec, jobs[:, order], brdf.cycles(jobs[:, 2], cfg))


def brdf_exhaustive_stimulus(
    cfg: units.UnitConfig, ns: Sequence[int] | None = None
) -> soak_stimulus.Stimulus:
    """The exhaustive check's lines (``brdf_exhaustive_jobs``) back to back."""
    assert isinstance(cfg, FixedConfig)
    return _lines_back_to_back(cfg, brdf_exhaustive_jobs(cfg, ns))


# The forms the exhaustive check gives no one-pixel lines (``EXHAUSTIVE_PIXELS``) get them for
# these n: 1 to 16 (the widest highlights) and 48 more spread evenly to 1000
PIXEL_SAMPLE_NS = (*range(1, 17), *(int(n) for n in np.linspace(17, 1000, 48).round()))
BRDF_PIXEL_SAMPLE = (
    f"one-pixel lines for {len(PIXEL_SAMPLE_NS)} n: the exhaustive check's one-pixel lines "
    "(each address whose word some C shows changed, at the C just below and the C just above a "
    "rounding point) for n 1 to 16 and 48 more spread to 1000, for a form whose exhaustive "
    "check has the top C's lines alone"
)


def _pixel_lines(ns: Sequence[int]) -> Callable[[units.UnitConfig], soak_stimulus.Stimulus]:
    """The stimulus of the one-pixel lines of ``brdf_exhaustive_jobs`` for ``ns``, back to
    back."""

    def stimulus(cfg: units.UnitConfig) -> soak_stimulus.Stimulus:
        assert isinstance(cfg, FixedConfig)
        return _lines_back_to_back(cfg, brdf_exhaustive_jobs(cfg, ns, lines=False, pixels=True))

    return stimulus


# The one-pixel lines for ``PIXEL_SAMPLE_NS``
brdf_pixel_sample_stimulus = _pixel_lines(PIXEL_SAMPLE_NS)


# The other n's one-pixel lines, after the sample, in PIXEL_REST_PARTS checks of every
# PIXEL_REST_PARTS-th n (each about 19M cycles, its file about 360 MB: one part's stimulus and
# prediction are held whole in memory): with the sample, every n's, and so the exhaustive
# check whole
PIXEL_REST_NS = tuple(n for n in range(1, N_MAX + 1) if n not in PIXEL_SAMPLE_NS)
PIXEL_REST_PARTS = 8


def brdf_pixel_rest(part: int) -> tuple[str, tuple[int, ...]]:
    """(name, ns) of the check ``part`` (0 to PIXEL_REST_PARTS - 1) of the other n's one-pixel
    lines: every PIXEL_REST_PARTS-th n of ``PIXEL_REST_NS`` from its ``part``-th."""
    if not 0 <= part < PIXEL_REST_PARTS:
        raise ValueError(f"part {part}: the parts are 0 to {PIXEL_REST_PARTS - 1}")
    ns = PIXEL_REST_NS[part::PIXEL_REST_PARTS]
    name = (
        f"one-pixel lines for the other n, part {part + 1} of {PIXEL_REST_PARTS}: the "
        f"exhaustive check's one-pixel lines for {len(ns)} n (every {PIXEL_REST_PARTS}th of "
        f"the {len(PIXEL_REST_NS)} the sample leaves out, from n = {ns[0]} to {ns[-1]}), for "
        "a form whose exhaustive check has the top C's lines alone"
    )
    return name, ns


def brdf_pixel_rest_stimulus(part: int) -> Callable[[units.UnitConfig], soak_stimulus.Stimulus]:
    """The stimulus of the check ``part`` of ``brdf_pixel_rest``: its n's one-pixel lines,
    back to back."""
    return _pixel_lines(brdf_pixel_rest(part)[1])


# The checks whose files run to millions of cycles (4M to 25M each): ``make mutants`` runs
# them, the quick tier's sample leaves their kills out
BRDF_LONG_CHECKS = (
    BRDF_EXHAUSTIVE,
    BRDF_PIXEL_SAMPLE,
    *(brdf_pixel_rest(part)[0] for part in range(PIXEL_REST_PARTS)),
)


# ---------------------------------------------------------------- the window of the fifth proof
# The cycle whose angle-table address is the checked pixel's: the schedule writes n in cycle 0
# and starts in cycle 1, so the line's word is in k_run_reg from cycle 2, and a line's first
# pixel has its address five edges after that (its w in cycle 7), as in a line the unit runs
WINDOW_PIXEL = 5


def brdf_window(cfg: FixedConfig) -> Window:
    """The BRDF unit's datapath as the fifth proof's window (sim/mutation_window.py,
    ``prove_window``): from the front's address register (S3, every value of it one the
    unit can hold: pi/2 and beyond read as w = 2^D) and the line's word k_run_reg (n written
    while idle, then a start) to the form's output word ``form_y``, two edges (the table read,
    the w gate) and the form's latency after the address.  ``tiny``: the smallest word that
    the largest C scales to an output above 0 (the model's rounding, ``scale_kernel``):
    C x word is rounded and saturated, non-decreasing in each, so a word below it shows 0 at
    every C."""
    a = cfg.angle
    words = np.arange(1 << cfg.out_bits, dtype=np.int64)
    shown = np.empty_like(words)
    scale_kernel(words, a.c_format.hi, a.c_frac_bits + cfg.out_bits, a.out_max, shown)
    tiny = int(np.argmax(shown > 0)) if shown.any() else 1 << cfg.out_bits
    return Window(
        cut="u_front.addr_reg",
        loaded=("k_run_reg",),
        idle="busy_reg",
        schedule=(("rst_n", "1'b1"), ("n_we", "t == 0"), ("start", "t == 1")),
        observe="form_y",
        frame=WINDOW_PIXEL + 2 + brdf.form_latency(cfg),
        tiny=tiny,
    )
