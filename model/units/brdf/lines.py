# SPDX-License-Identifier: Apache-2.0
"""BRDF family: many lines through the hardware unit in one call (the renderer's path).

``shade_lines`` is ``unit.unit_line`` for L lines, as ``specular.shade_lines`` is the specular
unit's ``shade_line`` for L lines: row j of its result equals ``unit_line(c[j], dz[j], z0[j],
n[j], length[j], cfg)``'s intensities, and its ``cycles`` are ``unit.cycles``.  The pipeline
(``model.render.pipeline``, a ``PipelineConfig`` with ``brdf`` set) sends its highlight jobs
here.  May import numpy, ``model.units.batch``, ``model.units.fixed`` and the package's
``fixed`` and ``unit``.
"""

from __future__ import annotations

import numpy as np

from model.units import batch
from model.units import fixed as fx
from model.units.brdf.fixed import FixedConfig, evaluate
from model.units.brdf.unit import check_unit, cycles, scale_kernel
from model.units.specular import N_MAX, N_WIDTH


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
    pixels, starts, offsets = batch.place_lines(len_a + 1, out, at, None)
    # Every pixel's accumulator value z0 + i dz (exact: acc_width bits never wrap), line by line
    line = np.repeat(np.arange(len_a.size), len_a + 1)
    index = np.arange(line.size, dtype=np.int64) - offsets[:-1][line]
    angles = z0_a[line] + index * dz_a[line]
    words = np.zeros(angles.size, dtype=np.int64)
    for n_j in np.unique(n_a):
        if 1 <= n_j <= N_MAX:  # any other n: n_err, and the unit's pixels are 0
            pick = n_a[line] == n_j
            words[pick] = evaluate(cfg, angles[pick], int(n_j))
    shift = a.c_frac_bits + cfg.out_bits
    for j in range(len_a.size):
        scale_kernel(words[offsets[j] : offsets[j + 1]], int(c_a[j]), shift, a.out_max,
                     pixels[starts[j] : starts[j] + len_a[j] + 1])  # fmt: skip
    return batch.LineBatch(pixels=pixels, offsets=offsets, cycles=np.asarray(cycles(len_a, cfg)))
