# SPDX-License-Identifier: Apache-2.0
"""Span beats for the shading core's benches (``model.render.core.SpanFormat``): random spans
with every field random in its range (the distribution of ``tests.test_core.random_words``,
from a ``random.Random`` so a bench's seed reproduces them), and the spans of the edge cases:
the shortest and longest span and a span whose sum saturates a channel."""

from __future__ import annotations

import random

from model.render import core
from model.render.pipeline import DIFFUSE_N


def random_row(
    fmt: core.SpanFormat, rng: random.Random, pixels: int, rows: range | None = None
) -> dict[str, int]:
    """The fields of one random span of ``pixels`` pixels (y in ``rows``, default every row):
    x so that the span fits the row, both flags, n over its whole field (0 and 1001.. are
    refused: tuser), intensities, C and angles over their whole ranges (dz shifted down by a
    random amount, so slow and fast sweeps both occur)."""
    g, s = fmt.cfg.gouraud, fmt.cfg.specular
    if not 1 <= pixels <= g.len_max:
        raise ValueError(f"pixels = {pixels} is out of range: legal range is 1..{g.len_max}")
    z_lo, z_hi = s.z_format.lo, s.z_format.hi
    rows = rows if rows is not None else range(1 << fmt.y_width)
    row = {
        "x": rng.randrange(0, (1 << fmt.x_width) - pixels + 1),
        "y": rng.choice(rows),
        "l": pixels - 1,
        "spec": rng.randrange(2),
        "diff": rng.randrange(2),
        "c": rng.randrange(1 << s.c_width),
        "dz": rng.randint(z_lo, z_hi) >> rng.randrange(16),
        "z0": rng.randint(z_lo, z_hi),
        "n": rng.randrange(1 << core.N_WIDTH),
        "diff_dz": rng.randint(z_lo, z_hi) >> rng.randrange(16),
        "diff_z0": rng.randint(z_lo, z_hi),
    }
    for c in range(core.CHANNELS):
        row[f"i_start{c}"] = rng.randrange(1 << g.i_width)
        row[f"i_end{c}"] = rng.randrange(1 << g.i_width)
        row[f"diff_c{c}"] = rng.randrange(1 << s.c_width)
    return row


def random_words(
    fmt: core.SpanFormat,
    count: int,
    rng: random.Random,
    lengths: list[int] | None = None,
    rows: range | None = None,
) -> list[int]:
    """``count`` random span beats (``random_row``); ``lengths``: the pixels of each (default
    1..23 at random, as ``tests.test_core.random_words``)."""
    layout = fmt.layout()
    words = []
    for i in range(count):
        pixels = lengths[i] if lengths is not None else rng.randint(1, 23)
        words.append(core.pack(layout, random_row(fmt, rng, pixels, rows)))
    return words


def saturating_rows(fmt: core.SpanFormat) -> list[dict[str, int]]:
    """Spans whose sum passes 255 in a channel: a bright Gouraud ramp (channel 0 near 255,
    channel 1 at mid grey, channel 2 dark) with the brightest highlight (C at its maximum,
    n = 1, the angle through 0), then with half that highlight (channel 1 sums to about 255),
    then with the brightest diffuse term on top; the last one a single pixel.
    ``core_pixels`` gives 255 where the sum passes it."""
    g, s = fmt.cfg.gouraud, fmt.cfg.specular
    top = (1 << g.i_width) - 1
    c_max = (1 << s.c_width) - 1
    dz = -(1 << (s.z_frac_bits - 6))  # a slow sweep through the peak
    base = {
        "x": 100,
        "y": 7,
        "l": 15,
        "spec": 1,
        "diff": 0,
        "i_start0": top,
        "i_end0": top - (40 << g.i_frac),
        "i_start1": 128 << g.i_frac,
        "i_end1": 150 << g.i_frac,
        "i_start2": 0,
        "i_end2": 8 << g.i_frac,
        "c": c_max,
        "dz": dz,
        "z0": -8 * dz,
        "n": 1,
    }
    diffuse = {"diff": 1, "diff_dz": dz, "diff_z0": -8 * dz}
    diffuse |= {f"diff_c{c}": c_max for c in range(core.CHANNELS)}
    return [
        base,
        {**base, "y": 6, "c": c_max // 2},  # a half highlight: channel 1 sums to about 255
        {**base, **diffuse, "y": 8},
        {**base, **diffuse, "y": 9, "l": 0, "z0": 0, "diff_z0": 0, "n": DIFFUSE_N},
    ]


def words_of(fmt: core.SpanFormat, rows: list[dict[str, int]]) -> list[int]:
    """The span beats of field dictionaries (``core.pack``)."""
    layout = fmt.layout()
    return [core.pack(layout, row) for row in rows]
