# SPDX-License-Identifier: Apache-2.0
"""BRDF family: many lines through the hardware unit in one call (the renderer's path).

``shade_lines`` is ``unit.unit_line`` for L lines, as ``specular.shade_lines`` is the specular
unit's ``shade_line`` for L lines: row j of its result equals ``unit_line(c[j], dz[j], z0[j],
n[j], length[j], cfg)``'s intensities, and its ``cycles`` are ``unit.cycles``.  The pipeline
(``model.render.pipeline``, a ``PipelineConfig`` with ``brdf`` set) sends its highlight jobs
here, and the vector soak's prediction (``sim/soak_predict.py``).  May import numpy, numba,
``model.units.batch``, ``model.units.fixed`` and the package's ``fixed`` and ``unit``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from model.units import batch
from model.units import fixed as fx
from model.units.brdf.fixed import FixedConfig, evaluate
from model.units.brdf.unit import check_unit, cycles, scale_kernel
from model.units.specular import N_MAX, N_WIDTH


@njit(cache=True)
def _scale_lines(words, c, offsets, starts, shift: int, out_max: int, pixels) -> None:
    """Line j's words (packed at offsets[j]) x C[j], rounded and saturated (``scale_kernel``,
    as ``unit.unit_line``), into pixels[starts[j]:]."""
    for j in range(c.size):
        lo, hi = offsets[j], offsets[j + 1]
        scale_kernel(words[lo:hi], c[j], shift, out_max, pixels[starts[j] : starts[j] + hi - lo])


def shade_lines(c, dz, z0, n, length, cfg: FixedConfig, out=None, at=None) -> batch.LineBatch:
    """``unit.unit_line`` for L lines in one call (pixels of an n outside 1..1000: 0).

    ``c``, ``dz``, ``z0``, ``n``, ``length`` are (L,) integer arrays (L = 0 allowed); ``out``
    and ``at`` place the lines as ``specular.shade_lines`` does (``batch.place_lines``).  A bad
    operand raises ``ValueError`` naming the row, its value and the legal range."""
    batch.check_rows({"c": c, "dz": dz, "z0": z0, "n": n, "length": length})
    a = check_unit(cfg).angle
    z_lo, z_hi = a.z_format.lo, a.z_format.hi
    c_a = fx.check_operand("c", c, 0, a.c_format.hi, rows=True)
    dz_a = fx.check_operand("dz", dz, z_lo, z_hi, rows=True)
    z0_a = fx.check_operand("z0", z0, z_lo, z_hi, rows=True)
    n_a = fx.check_operand("n", n, 0, (1 << N_WIDTH) - 1, rows=True)
    len_a = fx.check_operand("length", length, 0, a.len_max, rows=True)
    counts = len_a + 1
    pixels, starts, offsets = batch.place_lines(counts, out, at, None)
    total = int(offsets[-1])
    # Every pixel's accumulator value z0 + i dz (exact: acc_width bits never wrap), line by line
    step = np.arange(total, dtype=np.int64) - np.repeat(offsets[:-1], counts)
    angles = np.repeat(z0_a, counts) + step * np.repeat(dz_a, counts)
    # The form's word once per n over every pixel of the lines with that n (0: an n outside
    # 1..1000, whose pixels the unit makes 0 with n_err)
    ok = (n_a >= 1) & (n_a <= N_MAX)
    pixel_n = np.where(np.repeat(ok, counts), np.repeat(n_a, counts), 0)
    words = np.zeros(total, dtype=np.int64)
    order = np.argsort(pixel_n, kind="stable")
    values, first = np.unique(pixel_n[order], return_index=True)
    for v, lo, hi in zip(values.tolist(), first.tolist(), [*first[1:].tolist(), total],
                         strict=True):  # fmt: skip
        if v:
            words[order[lo:hi]] = evaluate(cfg, angles[order[lo:hi]], v)
    _scale_lines(words, c_a, offsets, starts, a.c_frac_bits + cfg.out_bits, a.out_max, pixels)
    return batch.LineBatch(pixels=pixels, offsets=offsets, cycles=np.asarray(cycles(len_a, cfg)))
