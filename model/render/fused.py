# SPDX-License-Identifier: Apache-2.0
"""The hybrid pipeline's fast paths: the units of a span in one numba kernel, summed to uint8.

``shade_spans`` takes one object's ``Spans`` and which spans go through the specular unit, and
does every step of ``pipeline`` per span in one kernel: the set-up (``specular.setup_row``, the
same code as ``setup_lines``) and the quantisation of the registers, the divider (its quotient
is ``a * round(2**N / k)``, the ROM word, exactly), the Gouraud pixels (``gouraud`` datapath
``lane_pixel``: the lane adders' closed form), the specular pixels (``specular`` datapath
``pixel_value``, the accumulator ``z0 + x dz``) and the sum, saturated, into the ``(pixels, C)``
uint8 output.  ``shade_jobs`` does the units and the sum from ``pipeline.UnitJobs`` (the same
operands the units receive) and the divider's ``di``.  Both give the bytes of ``run_units``
then ``assemble`` (``tests/test_fast_pipeline.py``); ``threads`` splits the spans over numba's
threads (``prange``).  The operands are checked against the units' ranges: ``shade_jobs``
raises the units' ``ValueError``; ``shade_spans`` returns None and the caller takes the
reference path, which raises it.  May import numpy, numba, ``model.units`` and
``model.render`` ``scene``, ``spans`` and ``vectors``.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from model.render.scene import Material
from model.render.spans import Spans
from model.render.vectors import LightingParams, light_view
from model.units import divider, fixed
from model.units.divider import DividerConfig
from model.units.gouraud import GouraudConfig
from model.units.gouraud import lane_pixel as gouraud_pixel
from model.units.specular import MIN_NORM, SpecularConfig, setup_row, tables
from model.units.specular import pixel_value as specular_pixel

DIFFUSE_N = 1
"""The exponent of the diffuse jobs (``pipeline.DIFFUSE_N``)."""
SPAN_FLOATS = (
    "n_start", "n_end", "h_start", "h_end", "p_start", "p_end", "g_start", "g_end", "s_start",
    "s_end",
)  # fmt: skip
"""The float arrays of ``Spans`` that ``shade_spans`` reads, in its kernel's order."""
THREAD_MIN_PIXELS = 1 << 15
"""Objects with fewer pixels run on one thread even with ``threads``: starting the threads
costs more than they save."""


@njit(cache=True, inline="always")
def _specular_line(
    spec, n_px, z0, dz, c_reg, a_word, t_sel, rom12, mag_max, shift, addr_bits, out_shift, s_max
) -> None:
    """The specular unit's ``n_px`` pixels into ``spec``: the accumulator, register 8, is
    ``z0 + x dz`` (an exact adder)."""
    for x in range(n_px):
        spec[x] = specular_pixel(
            z0 + x * dz, c_reg, a_word, t_sel, rom12, mag_max, shift, addr_bits, out_shift, s_max
        )


@njit(cache=True)
def _spans(
    first, stop, offsets, intervals, i_start, di, spec_job, spec_c, spec_dz, spec_z0, spec_n,
    diff_job, diff_c, diff_dz, diff_z0, g_args, rom9, tsel, rom12, s_args, out_max, out,
):  # fmt: skip
    """Spans first..stop-1: per pixel the specular term, then per channel Gouraud + diffuse
    + specular, saturated, into ``out``."""
    bias, frac, g_max = g_args[0], g_args[1], g_args[2]
    mag_max, shift, addr_bits = s_args[0], s_args[1], s_args[2]
    out_shift, s_max = s_args[3], s_args[4]
    a_diff, t_diff = rom9[DIFFUSE_N], tsel[DIFFUSE_N]
    spec = np.zeros(intervals.max() + 1 if intervals.size else 1, dtype=np.int64)
    for s in range(first, stop):
        lo = offsets[s]
        n_px = intervals[s] + 1
        j = spec_job[s]
        if j >= 0:
            a_word, t_sel = rom9[spec_n[j]], tsel[spec_n[j]]
            c_reg, z0, dz = spec_c[j], spec_z0[j], spec_dz[j]
            _specular_line(spec, n_px, z0, dz, c_reg, a_word, t_sel, rom12, mag_max, shift,
                           addr_bits, out_shift, s_max)  # fmt: skip
        else:
            for x in range(n_px):
                spec[x] = 0
        for c in range(i_start.shape[1]):
            i0, d_i = i_start[s, c], di[s, c]
            k = diff_job[s, c]
            if k >= 0:
                c_reg, z0, dz = diff_c[k], diff_z0[k], diff_dz[k]
                for x in range(n_px):
                    total = spec[x] + gouraud_pixel(i0, d_i, x, bias, frac, g_max)
                    total += specular_pixel(
                        z0 + x * dz, c_reg, a_diff, t_diff, rom12, mag_max, shift, addr_bits,
                        out_shift, s_max,
                    )  # fmt: skip
                    out[lo + x, c] = min(total, out_max)
            else:
                for x in range(n_px):
                    total = spec[x] + gouraud_pixel(i0, d_i, x, bias, frac, g_max)
                    out[lo + x, c] = min(total, out_max)


@njit(cache=True, parallel=True)
def _spans_parallel(chunks, *args) -> None:
    """``_spans`` over the chunks of spans ``chunks[t]..chunks[t + 1] - 1``, one per thread."""
    for t in prange(chunks.size - 1):
        _spans(chunks[t], chunks[t + 1], *args)


def _check(jobs, di: np.ndarray, g: GouraudConfig, sp: SpecularConfig) -> None:
    """The operand checks of ``gouraud.shade_lines`` and ``specular.shade_lines``."""
    fixed.check_operand("i0", jobs.i_start, *g.i0_range, rows=True)
    fixed.check_operand("di", di, *g.di_range, rows=True)
    fixed.check_operand("length", jobs.intervals + 1, 1, g.len_max, rows=True)
    z_lo, z_hi = sp.z_format.lo, sp.z_format.hi
    for prefix in ("spec", "diff"):
        fixed.check_operand("c", getattr(jobs, f"{prefix}_c"), 0, sp.c_format.hi, rows=True)
        fixed.check_operand("dz", getattr(jobs, f"{prefix}_dz"), z_lo, z_hi, rows=True)
        fixed.check_operand("z0", getattr(jobs, f"{prefix}_z0"), z_lo, z_hi, rows=True)
        used = jobs.intervals[getattr(jobs, f"{prefix}_span")]
        fixed.check_operand("length", used, 0, sp.len_max, rows=True)
    n_used = np.concatenate([jobs.spec_n, np.full(jobs.diff_span.size, DIFFUSE_N)])
    fixed.check_operand("n", n_used.astype(np.int64), sp.n_first, sp.n_last, rows=True)


def shade_jobs(
    jobs,
    di: np.ndarray,
    offsets: np.ndarray,
    g: GouraudConfig,
    sp: SpecularConfig,
    out_max: int = 255,
    threads: bool = False,
) -> np.ndarray:
    """(pixels, C) uint8: ``min(gouraud + diffuse + specular, out_max)`` of every span's pixels,
    span s at rows ``offsets[s] : offsets[s + 1]``, from ``jobs`` (a ``pipeline.UnitJobs``) and
    the Gouraud increments ``di`` (S, C); ``threads`` splits the spans over numba's threads."""
    _check(jobs, di, g, sp)
    spans, channels = jobs.i_start.shape
    spec_job = np.full(spans, -1, dtype=np.int64)
    spec_job[jobs.spec_span] = np.arange(jobs.spec_span.size)
    diff_job = np.full((spans, channels), -1, dtype=np.int64)
    diff_job[jobs.diff_span, jobs.diff_channel] = np.arange(jobs.diff_span.size)
    t = tables(sp)
    rom12, mag_max, shift, addr_bits, out_shift, s_max = t.pixel_args
    g_args = np.array([g.round_bias, g.i_frac, g.out_max, g.p], dtype=np.int64)
    s_args = np.array([mag_max, shift, addr_bits, out_shift, s_max], dtype=np.int64)
    out = np.empty((int(offsets[-1]), channels), dtype=np.uint8)
    args = (
        np.ascontiguousarray(offsets, dtype=np.int64),
        np.ascontiguousarray(jobs.intervals, dtype=np.int64),
        np.ascontiguousarray(jobs.i_start, dtype=np.int64),
        np.ascontiguousarray(di, dtype=np.int64),
        spec_job,
        *(np.ascontiguousarray(a, dtype=np.int64) for a in (jobs.spec_c, jobs.spec_dz)),
        *(np.ascontiguousarray(a, dtype=np.int64) for a in (jobs.spec_z0, jobs.spec_n)),
        diff_job,
        *(np.ascontiguousarray(a, dtype=np.int64) for a in (jobs.diff_c, jobs.diff_dz)),
        np.ascontiguousarray(jobs.diff_z0, dtype=np.int64),
        g_args,
        t.rom9,
        t.tsel,
        rom12,
        s_args,
        int(out_max),
    )
    if threads and spans > 1 and offsets[-1] >= THREAD_MIN_PIXELS:
        # Chunks of about equal pixel counts, a few per thread.
        n_chunks = min(spans, 64)
        cuts = np.searchsorted(offsets[1:], np.linspace(0, offsets[-1], n_chunks + 1)[1:-1])
        chunks = np.unique(np.concatenate([[0], cuts, [spans]]).astype(np.int64))
        _spans_parallel(chunks, *args, out)
    else:
        _spans(0, spans, *args, out)
    return out


# ------------------------------------------------------------------------------------------------
# One kernel from the spans: set-up, divider, units and sum (``shade_spans``)

# Integer parameters of ``_object_spans`` (one int64 array), by index.
(I_N, I_S_MAX, I_G_HI, I_G_BIAS, I_G_FRAC, I_G_MAX, I_A_LO, I_A_HI, I_DI_LO, I_DI_HI, I_RECIP,
 I_C_LO, I_C_HI, I_Z_LO, I_Z_HI, I_MAG, I_SHIFT, I_ADDR, I_OSHIFT, I_KIND, I_LOCAL, I_OUT_MAX,
 I_COUNT) = range(23)  # fmt: skip
# Float parameters: the scales 2**frac of the formats, k_s I_l.
F_G_SCALE, F_C_SCALE, F_Z_SCALE, F_LIGHT, F_COUNT = range(5)


@njit(cache=True, inline="always")
def quantise(x: float, scale: float, lo: int, hi: int) -> int:
    """``fixed.QFormat.quantise`` of one value (the same float operations): round half away
    from zero, saturate to lo..hi."""
    raw = np.sign(x) * np.floor(np.abs(x) * scale + 0.5)
    return int(min(max(raw, lo), hi))


@njit(cache=True)
def _unit_into(v: np.ndarray, out: np.ndarray) -> bool:
    """``setup._unit_rows`` of one row (v / |v|); False where it would refuse the row or scale
    it first (not finite, shorter than ``MIN_NORM``, |v| overflowing): the caller falls back."""
    norm = np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    if not (np.isfinite(v[0]) and np.isfinite(v[1]) and np.isfinite(v[2])):
        return False
    if not np.isfinite(norm) or norm < MIN_NORM:
        return False
    for i in range(3):
        out[i] = v[i] / norm
    return True


@njit(cache=True)
def _object_spans(
    first, stop, intervals, offsets, n_start, n_end, h_start, h_end, p_start, p_end, g_start,
    g_end, s_start, s_end, spec_flag, diff_flag, ip, fp, lvec, vvec, ambient, light_diff, words,
    rom9, tsel, rom12, out, status,
):  # fmt: skip
    """Spans first..stop-1 from their end values to uint8 pixels: ``build_jobs``' set-up and
    quantisation, the divider, the units and the sum, per span.  ``status[0]`` = 1 (and
    return) where an operand is out of a unit's range: the caller then takes the reference
    path, which raises the unit's ``ValueError``."""
    channels = g_start.shape[1]
    n_mat, s_max = ip[I_N], ip[I_S_MAX]
    mag_max, shift, addr_bits, out_shift = ip[I_MAG], ip[I_SHIFT], ip[I_ADDR], ip[I_OSHIFT]
    bias, frac, g_max = ip[I_G_BIAS], ip[I_G_FRAC], ip[I_G_MAX]
    longest = intervals.max() + 1 if intervals.size else 1
    spec = np.zeros(longest, dtype=np.int64)
    i0s = np.zeros(channels, dtype=np.int64)
    dis = np.zeros(channels, dtype=np.int64)
    dregs = np.zeros((channels, 3), dtype=np.int64)
    vecs = np.zeros((6, 3))  # N1, N2, H1, H2, L1, L2 as unit vectors
    row = np.zeros(6)
    p = np.zeros(3)
    a_spec, t_spec = rom9[n_mat], tsel[n_mat]
    a_diff, t_diff = rom9[DIFFUSE_N], tsel[DIFFUSE_N]
    half_q = 1 << (ip[I_RECIP] - 1)
    for s in range(first, stop):
        l_int = intervals[s]
        n_px = l_int + 1
        vertex = not spec_flag[s]
        for c in range(channels):  # steps 1 and 2: span-end intensities, the increment
            gs, ge = g_start[s, c], g_end[s, c]
            if diff_flag[s]:
                gs, ge = ambient[c], ambient[c]
            if vertex:
                gs, ge = gs + s_start[s], ge + s_end[s]
            i0 = quantise(gs, fp[F_G_SCALE], 0, ip[I_G_HI])
            i0s[c] = i0
            dis[c] = 0
            if l_int > 0:
                a = quantise(ge, fp[F_G_SCALE], 0, ip[I_G_HI]) - i0
                if a < ip[I_A_LO] or a > ip[I_A_HI]:
                    status[0] = 1
                    return
                dis[c] = (a * words[l_int] + half_q) >> ip[I_RECIP]  # divider, then round
                if dis[c] < ip[I_DI_LO] or dis[c] > ip[I_DI_HI]:
                    status[0] = 1
                    return
        if spec_flag[s] or diff_flag[s]:  # the set-up's unit vectors
            ok = _unit_into(n_start[s], vecs[0]) and _unit_into(n_end[s], vecs[1])
            if not ok:
                status[0] = 1
                return
        if spec_flag[s]:  # step 4: the highlight's registers, then its pixels
            if not (_unit_into(h_start[s], vecs[2]) and _unit_into(h_end[s], vecs[3])):
                status[0] = 1
                return
            setup_row(vecs[0], vecs[1], vecs[2], vecs[3], n_mat, fp[F_LIGHT], l_int, s_max, row)
            c_reg = quantise(row[3], fp[F_C_SCALE], ip[I_C_LO], ip[I_C_HI])
            dz = quantise(row[4], fp[F_Z_SCALE], ip[I_Z_LO], ip[I_Z_HI])
            z0 = quantise(row[5], fp[F_Z_SCALE], ip[I_Z_LO], ip[I_Z_HI])
            _specular_line(spec, n_px, z0, dz, c_reg, a_spec, t_spec, rom12, mag_max, shift,
                           addr_bits, out_shift, s_max)  # fmt: skip
        else:
            for x in range(n_px):
                spec[x] = 0
        if diff_flag[s]:  # step 4b: L at the span ends, one job per channel at n = 1
            for e in range(2):
                p[:] = p_start[s] if e == 0 else p_end[s]
                lv = light_view(p[0], p[1], p[2], ip[I_KIND], lvec, ip[I_LOCAL], vvec)
                p[0], p[1], p[2] = lv[0], lv[1], lv[2]
                if not _unit_into(p, vecs[4 + e]):
                    status[0] = 1
                    return
            for c in range(channels):
                setup_row(
                    vecs[0], vecs[1], vecs[4], vecs[5], DIFFUSE_N, light_diff[c], l_int, s_max,
                    row,
                )  # fmt: skip
                dregs[c, 0] = quantise(row[3], fp[F_C_SCALE], ip[I_C_LO], ip[I_C_HI])
                dregs[c, 1] = quantise(row[4], fp[F_Z_SCALE], ip[I_Z_LO], ip[I_Z_HI])
                dregs[c, 2] = quantise(row[5], fp[F_Z_SCALE], ip[I_Z_LO], ip[I_Z_HI])
        lo = offsets[s]
        for c in range(channels):  # steps 3 and 5: Gouraud, + diffuse + specular, saturate
            i0, d_i = i0s[c], dis[c]
            if diff_flag[s]:
                c_reg, dz, z0 = dregs[c, 0], dregs[c, 1], dregs[c, 2]
                for x in range(n_px):
                    total = spec[x] + gouraud_pixel(i0, d_i, x, bias, frac, g_max)
                    total += specular_pixel(
                        z0 + x * dz, c_reg, a_diff, t_diff, rom12, mag_max, shift, addr_bits,
                        out_shift, s_max,
                    )  # fmt: skip
                    out[lo + x, c] = min(total, ip[I_OUT_MAX])
            else:
                for x in range(n_px):
                    total = spec[x] + gouraud_pixel(i0, d_i, x, bias, frac, g_max)
                    out[lo + x, c] = min(total, ip[I_OUT_MAX])


@njit(cache=True, parallel=True)
def _object_parallel(chunks, *args) -> None:
    """``_object_spans`` over the chunks of spans ``chunks[t]..chunks[t + 1] - 1``."""
    for t in prange(chunks.size - 1):
        _object_spans(chunks[t], chunks[t + 1], *args)


_WORDS: dict[DividerConfig, np.ndarray] = {}


def shade_spans(
    spans: Spans,
    spec_flag: np.ndarray,
    diff_flag: np.ndarray,
    material: Material,
    lighting: LightingParams,
    d: DividerConfig,
    g: GouraudConfig,
    sp: SpecularConfig,
    out_max: int = 255,
    threads: bool = False,
) -> np.ndarray | None:
    """(pixels, C) uint8 of one object's spans, every step in one kernel: the same bytes as
    ``pipeline.build_jobs``, ``run_units`` and ``assemble`` (``spec_flag``, ``diff_flag``: the
    spans through the specular unit, for the highlight and for the diffuse term).  The caller
    checks the span lengths and n; None where an operand is out of a unit's range (the
    caller's reference path then raises the unit's error)."""
    if d not in _WORDS:
        _WORDS[d] = divider.rom_words(d)
    t = tables(sp)
    rom12, mag_max, shift, addr_bits, out_shift, s_max = t.pixel_args
    i0_hi = g.i0_range[1]
    ip = np.zeros(I_COUNT, dtype=np.int64)
    ip[:] = (
        material.n, s_max, i0_hi, g.round_bias, g.i_frac, g.out_max, *d.a_range, *g.di_range,
        d.recip_bits, sp.c_format.lo, sp.c_format.hi, sp.z_format.lo, sp.z_format.hi, mag_max,
        shift, addr_bits, out_shift, lighting.light_kind, lighting.viewer_local, out_max,
    )  # fmt: skip
    fp = np.zeros(F_COUNT)
    fp[:] = (
        2.0**g.i0_format.frac_bits,
        2.0**sp.c_format.frac_bits,
        2.0**sp.z_format.frac_bits,
        material.k_s * lighting.intensity,
    )
    colour = np.asarray(material.colour, dtype=np.float64)
    f64 = np.float64
    out = np.empty((spans.n_pixels, spans.g_start.shape[1]), dtype=np.uint8)
    status = np.zeros(1, dtype=np.int64)
    args = (
        spans.x_end - spans.x_start, spans.offsets,
        *(np.ascontiguousarray(getattr(spans, name), dtype=f64) for name in SPAN_FLOATS),
        np.ascontiguousarray(spec_flag, dtype=np.bool_),
        np.ascontiguousarray(diff_flag, dtype=np.bool_),
        ip, fp, np.asarray(lighting.lvec, dtype=f64), np.asarray(lighting.vvec, dtype=f64),
        255.0 * colour * material.ambient, material.k_d * colour * lighting.intensity,
        _WORDS[d], t.rom9, t.tsel, rom12, out, status,
    )  # fmt: skip
    count = len(spans)
    if threads and count > 1 and spans.n_pixels >= THREAD_MIN_PIXELS:
        cuts = np.searchsorted(spans.offsets[1:], np.linspace(0, spans.n_pixels, 65)[1:-1])
        chunks = np.unique(np.concatenate([[0], cuts, [count]]).astype(np.int64))
        _object_parallel(chunks, *args)
    else:
        _object_spans(0, count, *args)
    return None if status[0] else out
