# SPDX-License-Identifier: Apache-2.0
"""The hybrid shading pipeline: spans from the float rasteriser through the bit-exact units.

Per span of ``l`` intervals (``l + 1`` pixels), as the patent's external device would drive them:

1. **Gouraud intensities at the span ends** (ambient + diffuse per colour channel, 8-bit levels,
   from the rasteriser) are quantised to the Gouraud unit's unsigned Q8.f format
   (round half away from zero, saturated: ``QFormat.quantise``).
2. **The increment** ``dI = (I_end - I_start) / l`` comes from the shift-add divider: dividend
   ``a = I_end - I_start`` (signed, the difference of two Q8.f values), divisor ``k = l``.  Its
   quotient has ``f + N`` fraction bits; the named step ``increment_from_quotient`` rounds it to
   the Gouraud ``di`` format (round half up, ``fixed.round_shift``).  A one-pixel span (l = 0)
   needs no division: dI = 0.
3. **The segment Gouraud unit** turns (I_start, dI, l + 1) into the span's pixels, per channel.
4. **The specular unit** (methods that use it): ``specular.setup_line`` from the span-end N, H,
   the material's n and k_s * I_l gives the registers C, dz, z0; the unit gives l + 1
   intensities of the (white) highlight.
4b. **The diffuse term through the specular unit** (``diffuse_mode`` "unit" or "adaptive"): the
   same unit at n = 1 (its k = 1 table, a = 1) computes ``C cos(zeta)``, the Lambert term with
   spherically interpolated N, from the same set-up with L in place of H: one job per colour
   channel with C = k_d * colour_c * I_l.  The Gouraud unit then carries only the ambient term
   (and the vertex specular where the highlight is not made by the unit).
5. **Sum and saturate**: each channel is ``min(gouraud + diffuse + specular, 255)``.

Every pixel value comes out of the unit models: on the reference path through their batched
public calls (``divider.divide_many``, ``gouraud.shade_lines``, ``specular.shade_lines``: each
row equals the per-line call); the float work is only the set-up (1, 4).  The same steps run on
RTL outputs in the scene co-simulation (``sim/scene_cosim.py``): the jobs each unit receives
are ``UnitJobs`` and the image is assembled from the units' outputs by ``assemble``, so the
model image and the RTL image differ only if a unit does.  ``unit_shader`` runs, by default,
the same steps for one object in one numba kernel (``fused.shade_spans``, from the units'
public per-pixel kernels), byte for byte the reference path's image (``SHADER_PATHS``;
``tests/test_fast_pipeline.py``).

Methods (``METHODS``): the hybrid with the patent's k-set and a = sqrt(n/k), the same with the
thesis's inflection-matched a, the prototype's single cos^2 table, Gouraud only (the specular
term evaluated at the vertices and interpolated with the diffuse one: no specular unit), the
structure-adaptive method (the specular unit only on triangles the highlight test flags), and
the hybrid with the diffuse term through the specular unit at n = 1 as well ("diffuse");
``BRDF_METHODS``: the hybrid with the highlight through a BRDF family unit.

Size: about 530 lines: the five steps, the jobs every unit receives, the routes of the spans
and the shader paths are one pipeline, which the co-simulations run step by step.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from model.render import fused
from model.render.highlight import span_highlight_flags
from model.render.reference import object_diffuse_flags
from model.render.shade import ShadeContext, ShadeResult
from model.render.spans import Spans
from model.render.vectors import lighting_vectors
from model.units import brdf, divider, gouraud, specular
from model.units.brdf import lines as brdf_lines
from model.units.brdf import unit as brdf_unit

SPECULAR_MODES = ("unit", "vertex", "adaptive")
DIFFUSE_MODES = ("gouraud", "unit", "adaptive")
DIFFUSE_N = 1
"""The exponent of the diffuse jobs: the specular unit's k = 1 table with a = 1, C cos(zeta)."""


@dataclass(frozen=True)
class PipelineConfig:
    """The units' configurations and how the specular and the diffuse terms are made.

    ``specular_mode``: "unit" (every span through the specular unit), "vertex" (Gouraud only:
    specular at the vertices, interpolated by the Gouraud unit), "adaptive" (the unit on the
    triangles ``reference.object_highlight_flags`` marks at ``highlight_levels``, vertex
    specular elsewhere).

    ``diffuse_mode``: "gouraud" (ambient + diffuse lit at the vertices and interpolated by the
    Gouraud unit), "unit" (every span's diffuse term through the specular unit at n = 1, one job
    per colour channel; the Gouraud unit carries the ambient term only), "adaptive" (the unit
    on the triangles ``reference.object_diffuse_flags`` marks: vertex normals spread by more
    than ``diffuse_spread_deg`` degrees; Gouraud diffuse elsewhere).  The diffuse jobs need a
    specular unit that keeps n = 1 (``SpecularConfig.n_first`` = 1).

    ``brdf``: None (the highlight through the patent's specular unit), or a ``brdf.FixedConfig``
    of a form with RTL (``brdf.unit.RTL_FORMS``): the highlight jobs, with the same registers
    (``specular.setup_lines`` in ``specular``'s formats, which the form's ``angle`` must share),
    go through that BRDF unit instead (``brdf.lines.shade_lines``); the diffuse term is then
    Gouraud's.
    """

    divider: divider.DividerConfig = divider.DEFAULT
    gouraud: gouraud.GouraudConfig = gouraud.DEFAULT
    specular: specular.SpecularConfig = specular.DEFAULT
    specular_mode: str = "unit"
    highlight_levels: float = 0.5
    diffuse_mode: str = "gouraud"
    diffuse_spread_deg: float = 10.0
    brdf: brdf.FixedConfig | None = None

    def __post_init__(self) -> None:
        if self.brdf is not None:
            self._check_brdf()
        if self.specular_mode not in SPECULAR_MODES:
            raise ValueError(
                f"specular_mode = {self.specular_mode!r} is out of range: legal values are "
                f"{', '.join(SPECULAR_MODES)}"
            )
        if self.diffuse_mode not in DIFFUSE_MODES:
            raise ValueError(
                f"diffuse_mode = {self.diffuse_mode!r} is out of range: legal values are "
                f"{', '.join(DIFFUSE_MODES)}"
            )
        n_first = self.specular.n_first  # the smallest n ROM 9 keeps
        if self.diffuse_mode != "gouraud" and n_first > DIFFUSE_N:
            raise ValueError(
                f"diffuse_mode = {self.diffuse_mode!r} is out of range for a specular unit that "
                f"keeps n = {n_first}..: the diffuse jobs need n = {DIFFUSE_N}; legal values "
                "are gouraud, or a specular unit with n_first = 1"
            )
        if not 0 <= self.diffuse_spread_deg <= 180:
            raise ValueError(
                f"diffuse_spread_deg = {self.diffuse_spread_deg} is out of range: legal range "
                "is 0..180 (degrees)"
            )
        g, d = self.gouraud, self.divider
        if d.a_width < g.di_width:
            raise ValueError(
                f"divider a_width = {d.a_width} is out of range for Gouraud Q{g.i_int}."
                f"{g.i_frac}: the difference of two intensities needs {g.di_width} bits"
            )
        if d.k_max < g.len_max - 1 or self.specular.len_max < g.len_max - 1:
            raise ValueError(
                f"divider k_max = {d.k_max} and specular len_max = {self.specular.len_max} "
                f"must reach the longest Gouraud line's intervals, {g.len_max - 1}"
            )
        if not self.highlight_levels > 0:
            raise ValueError(
                f"highlight_levels = {self.highlight_levels} is out of range: legal is > 0"
            )

    def _check_brdf(self) -> None:
        brdf_unit.check_unit(self.brdf)
        if self.specular_mode == "vertex" or self.diffuse_mode != "gouraud":
            raise ValueError(
                f"brdf = {self.brdf.form!r} is out of range with specular_mode = "
                f"{self.specular_mode!r} and diffuse_mode = {self.diffuse_mode!r}: a BRDF unit "
                "makes the highlight only; legal are specular_mode unit or adaptive with "
                "diffuse_mode gouraud"
            )
        for name in brdf_unit.ANGLE_FIELDS:
            got, want = getattr(self.brdf.angle, name), getattr(self.specular, name)
            if got != want:
                raise ValueError(
                    f"brdf angle {name} = {got} is out of range: the highlight registers come "
                    f"in the specular configuration's formats, legal is {want}"
                )

    @property
    def uses_specular_unit(self) -> bool:
        """True when some span may go through the specular unit (highlight or diffuse)."""
        return self.specular_mode != "vertex" or self.diffuse_mode != "gouraud"


METHODS: dict[str, PipelineConfig] = {
    "hybrid": PipelineConfig(),
    "inflection": PipelineConfig(specular=specular.INFLECTION),
    "prototype": PipelineConfig(specular=specular.PROTOTYPE),
    "gouraud": PipelineConfig(specular_mode="vertex"),
    "adaptive": PipelineConfig(specular_mode="adaptive"),
    "diffuse": PipelineConfig(diffuse_mode="unit"),
}
BRDF_METHODS: dict[str, PipelineConfig] = {
    form: PipelineConfig(brdf=cfg) for form, cfg in brdf_unit.UNIT_CONFIGS.items()
}
"""The hybrid with the highlight through a BRDF family unit (each form with RTL, its default
widths) in place of the patent's specular unit: methods of ``shading demo``.  The shading core
takes them too (its ``HIGHLIGHT`` parameter: ``core.core_parameters``, the form's pipe
rtl/shading_brdf_pipe.v, a latency of its own, ``core.latency``; ``python -m sim bench`` runs
them through it).  They are kept apart from ``METHODS``, whose every entry runs the fused
shader kernels (the patent's unit only; a BRDF method takes the reference path)."""


# ------------------------------------------------------------------------------------------------
# Step 1 and 2: span-end intensities and the increment


def quantise_intensity(levels: np.ndarray, cfg: gouraud.GouraudConfig) -> np.ndarray:
    """Span-end intensities (8-bit levels, float) as Gouraud ``i0`` register values."""
    return np.asarray(cfg.i0_format.quantise(np.asarray(levels, dtype=np.float64)), dtype=np.int64)


def increment_from_quotient(q: np.ndarray, cfg: PipelineConfig) -> np.ndarray:
    """The divider's quotient (f + N fraction bits) rounded to the Gouraud ``di`` format.

    Round half up: add 2**(N-1), arithmetic shift by N (what ``fixed.round_shift`` does).  It
    cannot leave the ``di`` range: |q / 2**N| <= |a| for every k >= 1.
    """
    n = cfg.divider.recip_bits
    return (np.asarray(q, dtype=np.int64) + (1 << (n - 1))) >> n


@dataclass
class UnitJobs:
    """What one object's spans send to each unit, in span order.

    Gouraud: ``i_start``, ``i_end`` (S, C) register values, ``intervals`` (S,).
    Divider jobs are the (span, channel) pairs with l >= 1: a = i_end - i_start, k = l.
    Specular: ``spec_span`` indexes the spans that go through the unit, with their registers.
    Diffuse (the specular unit at n = ``DIFFUSE_N``): one job per (``diff_span``,
    ``diff_channel``), span-major, with its registers ``diff_c``, ``diff_dz``, ``diff_z0``; the
    specular unit receives them after the specular jobs.
    """

    intervals: np.ndarray
    i_start: np.ndarray
    i_end: np.ndarray
    spec_span: np.ndarray
    spec_c: np.ndarray
    spec_dz: np.ndarray
    spec_z0: np.ndarray
    spec_n: np.ndarray
    diff_span: np.ndarray
    diff_channel: np.ndarray
    diff_c: np.ndarray
    diff_dz: np.ndarray
    diff_z0: np.ndarray
    counters: dict[str, int] = field(default_factory=dict)

    @property
    def diff_n(self) -> np.ndarray:
        """The diffuse jobs' exponent register: n = 1 for every job."""
        return np.full(self.diff_span.size, DIFFUSE_N, dtype=np.int64)

    @property
    def divider_pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """(span, channel) of every division, row-major: the order the divider sees them."""
        spans, channels = np.nonzero(
            np.broadcast_to(self.intervals[:, None] > 0, self.i_start.shape)
        )
        return spans, channels

    def divider_operands(self) -> tuple[np.ndarray, np.ndarray]:
        s, c = self.divider_pairs
        return self.i_end[s, c] - self.i_start[s, c], self.intervals[s]

    def increments(self, quotients: np.ndarray, cfg: PipelineConfig) -> np.ndarray:
        """(S, C) ``di`` from the divider's quotients (0 for one-pixel spans)."""
        di = np.zeros_like(self.i_start)
        s, c = self.divider_pairs
        di[s, c] = increment_from_quotient(quotients, cfg)
        return di


# ------------------------------------------------------------------------------------------------
# Building the jobs, assembling the image


def build_jobs(spans: Spans, ctx: ShadeContext, cfg: PipelineConfig) -> UnitJobs:
    """The operands every unit receives for one object's spans (float set-up + quantisation)."""
    intervals, through_unit, diffuse_unit = span_routes(spans, ctx, cfg)
    g_start, g_end = spans.g_start.copy(), spans.g_end.copy()
    # With the diffuse term from the specular unit, the Gouraud unit carries the ambient term.
    m = ctx.material
    ambient = 255.0 * np.asarray(m.colour, dtype=np.float64) * m.ambient
    g_start[diffuse_unit] = ambient
    g_end[diffuse_unit] = ambient
    # Without the unit, the specular term is evaluated at the vertices and interpolated with
    # the diffuse one (classic Gouraud): it joins every channel of the span-end intensities.
    vertex = ~through_unit
    g_start[vertex] += spans.s_start[vertex, None]
    g_end[vertex] += spans.s_end[vertex, None]
    spec_span = np.nonzero(through_unit)[0].astype(np.int64)
    regs = _specular_registers(spans, ctx, cfg, spec_span, intervals)
    channels = g_start.shape[1]
    diff_span = np.repeat(np.nonzero(diffuse_unit)[0].astype(np.int64), channels)
    diff_channel = np.tile(np.arange(channels, dtype=np.int64), diff_span.size // channels)
    diff = _diffuse_registers(spans, ctx, cfg, diff_span, diff_channel, intervals)
    return UnitJobs(
        intervals=intervals,
        i_start=quantise_intensity(g_start, cfg.gouraud),
        i_end=quantise_intensity(g_end, cfg.gouraud),
        spec_span=spec_span,
        spec_c=regs[0],
        spec_dz=regs[1],
        spec_z0=regs[2],
        spec_n=np.full(spec_span.size, ctx.material.n, dtype=np.int64),
        diff_span=diff_span,
        diff_channel=diff_channel,
        diff_c=diff[0],
        diff_dz=diff[1],
        diff_z0=diff[2],
    )


def span_routes(spans: Spans, ctx: ShadeContext, cfg: PipelineConfig):
    """(intervals, through the specular unit, diffuse through the unit) per span, checked: a
    span too long for the units, or a material n the specular unit does not keep, raises."""
    intervals = (spans.x_end - spans.x_start).astype(np.int64)
    if intervals.size and intervals.max() > cfg.gouraud.len_max - 1:
        raise ValueError(
            f"span of {int(intervals.max()) + 1} pixels is out of range: the units take lines of "
            f"1..{cfg.gouraud.len_max} pixels"
        )
    through_unit = _spans_through_specular_unit(spans, ctx, cfg)
    diffuse_unit = _spans_with_diffuse_unit(spans, ctx, cfg)
    s = cfg.specular
    if through_unit.any() and not s.n_first <= ctx.material.n <= s.n_last:
        raise ValueError(
            f"material n = {ctx.material.n} (object {ctx.obj}) is out of range for this "
            f"specular unit: legal range is {s.n_first}..{s.n_last} (its ROM 9 keeps only "
            "those n: a unit fitted to a scene holds the n that scene used)"
        )
    return intervals, through_unit, diffuse_unit


def _drawn_triangle_flags(spans: Spans, mode: str, always: str, never: str, test) -> np.ndarray:
    """Per span: True for every span in mode ``always``, False in mode ``never``, else the host's
    per-triangle ``test`` of its triangle (the host tests each triangle it draws once, not the
    hidden or culled ones)."""
    if mode in (always, never):
        return np.full(len(spans), mode == always, dtype=bool)
    drawn, index = np.unique(spans.tri, return_inverse=True)
    return test(drawn)[index]


def _spans_through_specular_unit(spans: Spans, ctx: ShadeContext, cfg: PipelineConfig):
    """The highlight test's flag per span: ``highlight.span_highlight_flags`` (the kernel,
    ``reference.object_highlight_flags``' decisions) tests each drawn triangle once."""
    if cfg.specular_mode != "adaptive":
        return np.full(len(spans), cfg.specular_mode == "unit", dtype=bool)
    flags, _ = span_highlight_flags(
        ctx.scene, spans.tri, obj=ctx.obj, levels=cfg.highlight_levels, params=ctx.lighting
    )
    return flags


def _spans_with_diffuse_unit(spans: Spans, ctx: ShadeContext, cfg: PipelineConfig):
    return _drawn_triangle_flags(
        spans,
        cfg.diffuse_mode,
        "unit",
        "gouraud",
        lambda drawn: object_diffuse_flags(
            ctx.scene, obj=ctx.obj, spread_deg=cfg.diffuse_spread_deg, triangles=drawn
        ),
    )


def _specular_registers(
    spans: Spans, ctx: ShadeContext, cfg: PipelineConfig, spec_span: np.ndarray, intervals
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    setup = specular.setup_lines(
        spans.n_start[spec_span],
        spans.n_end[spec_span],
        spans.h_start[spec_span],
        spans.h_end[spec_span],
        ctx.material.n,
        ctx.material.k_s * ctx.lighting.intensity,
        intervals[spec_span],
        cfg.specular,
    )
    return setup.c_reg, setup.dz_reg, setup.z0_reg


def _diffuse_registers(
    spans: Spans,
    ctx: ShadeContext,
    cfg: PipelineConfig,
    diff_span: np.ndarray,
    diff_channel: np.ndarray,
    intervals: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The diffuse jobs' registers: ``setup_lines`` at n = 1 with L at the span ends in place
    of H and light = k_d * colour_c * I_l (C cos(zeta) = 255 k_d colour_c I_l max(0, N.L))."""
    m = ctx.material
    l_start, _, _ = lighting_vectors(spans.p_start[diff_span], ctx.lighting)
    l_end, _, _ = lighting_vectors(spans.p_end[diff_span], ctx.lighting)
    light = m.k_d * np.asarray(m.colour, dtype=np.float64)[diff_channel] * ctx.lighting.intensity
    setup = specular.setup_lines(
        spans.n_start[diff_span],
        spans.n_end[diff_span],
        l_start,
        l_end,
        DIFFUSE_N,
        light,
        intervals[diff_span],
        cfg.specular,
    )
    return setup.c_reg, setup.dz_reg, setup.z0_reg


def assemble(
    gouraud_out: np.ndarray,
    specular_out: np.ndarray,
    out_max: int = 255,
    diffuse_out: np.ndarray | None = None,
) -> np.ndarray:
    """Step 5: every channel = min(gouraud + diffuse + specular, out_max), as uint8 pixels
    (``diffuse_out``, (pixels, C), 0 where omitted)."""
    total = gouraud_out + specular_out[:, None]
    if diffuse_out is not None:
        total = total + diffuse_out
    return np.minimum(total, out_max).astype(np.uint8)


def unit_counters(jobs: UnitJobs, cfg: PipelineConfig) -> dict[str, int]:
    """Hardware cost of the jobs, from the models' cycle counts (start-to-start clocks).  The
    diffuse jobs run on the specular unit too; they are counted apart (``diffuse_*``)."""
    channels = jobs.i_start.shape[1]
    spec_l, diff_l = jobs.intervals[jobs.spec_span], jobs.intervals[jobs.diff_span]
    return route_counters(jobs.intervals, spec_l, diff_l, channels, cfg)


def route_counters(
    intervals: np.ndarray, spec_l: np.ndarray, diff_l: np.ndarray, channels: int, cfg
) -> dict[str, int]:
    """``unit_counters`` from the spans' intervals, those of the specular jobs and those of
    the diffuse jobs (one per channel)."""
    k = intervals[intervals > 0]  # one division per channel of every span with l >= 1
    return {
        "divider_jobs": int(k.size) * channels,
        "divider_cycles": channels * int((divider.cycles(k, cfg.divider) + 1).sum())
        if k.size
        else 0,
        "gouraud_jobs": int(intervals.size * channels),
        "gouraud_cycles": channels * int((gouraud.cycles(intervals + 1, cfg.gouraud) + 1).sum()),
        "specular_jobs": int(spec_l.size),
        "specular_pixels": int((spec_l + 1).sum()),
        "specular_cycles": int((_highlight_cycles(spec_l, cfg) + 1).sum()),
        "diffuse_jobs": int(diff_l.size),
        "diffuse_pixels": int((diff_l + 1).sum()),
        "diffuse_cycles": int((specular.cycles(diff_l, cfg.specular) + 1).sum()),
    }


def _highlight_cycles(spec_l: np.ndarray, cfg: PipelineConfig) -> np.ndarray:
    """Busy cycles of the highlight jobs on the unit that makes them (specular or BRDF)."""
    if cfg.brdf is not None:
        return np.asarray(brdf_unit.cycles(spec_l, cfg.brdf))
    return np.asarray(specular.cycles(spec_l, cfg.specular))


def run_units(jobs: UnitJobs, offsets: np.ndarray, cfg: PipelineConfig):
    """The model's outputs for the jobs: (gouraud (pixels, C), specular (pixels,), diffuse
    (pixels, C)), span s at rows ``offsets[s] : offsets[s + 1]``; 0 on the spans that do not
    go through the specular unit (for the highlight, or for the diffuse term).  Every value
    comes from the units' batched public calls."""
    a, k = jobs.divider_operands()
    q, _ = divider.divide_many(a, k, cfg.divider)
    di = jobs.increments(q, cfg)
    starts = offsets[:-1]
    channels = jobs.i_start.shape[1]
    npix = int(offsets[-1])
    g_out = np.zeros((npix, channels), dtype=np.int64)
    gouraud.shade_lines(jobs.i_start, di, jobs.intervals + 1, cfg.gouraud, out=g_out, at=starts)
    s_out = np.zeros(npix, dtype=np.int64)
    highlight = specular.shade_lines if cfg.brdf is None else brdf_lines.shade_lines
    highlight(
        jobs.spec_c,
        jobs.spec_dz,
        jobs.spec_z0,
        jobs.spec_n,
        jobs.intervals[jobs.spec_span],
        cfg.specular if cfg.brdf is None else cfg.brdf,
        out=s_out,
        at=starts[jobs.spec_span],
    )
    # The diffuse lines into a channel-major flat buffer: channel c's pixel p at c * npix + p.
    d_flat = np.zeros(channels * npix, dtype=np.int64)
    specular.shade_lines(
        jobs.diff_c,
        jobs.diff_dz,
        jobs.diff_z0,
        jobs.diff_n,
        jobs.intervals[jobs.diff_span],
        cfg.specular,
        out=d_flat,
        at=jobs.diff_channel * npix + starts[jobs.diff_span],
    )
    return g_out, s_out, d_flat.reshape(channels, npix).T


SHADER_PATHS = ("fused", "threads", "jobs", "units")
"""``unit_shader``'s paths, the same image by each: one kernel per object from the spans to
the pixels (``fused.shade_spans``), the same over numba's threads, ``build_jobs`` then one
kernel for the units and the sum (``fused.shade_jobs``), or ``build_jobs``, the units' batched
calls and ``assemble`` (the reference path: what the scene co-simulation runs)."""


def shade_pixels(jobs: UnitJobs, offsets: np.ndarray, cfg: PipelineConfig, path: str = "fused"):
    """Steps 2-5 for one object's jobs: the (pixels, C) uint8 image, by ``path``
    (``SHADER_PATHS``); every path gives the same bytes (a BRDF unit's highlight has the
    reference path only: the fused kernels hold the patent's unit)."""
    if path == "units" or (cfg.brdf is not None and path in SHADER_PATHS):
        gouraud_out, specular_out, diffuse_out = run_units(jobs, offsets, cfg)
        return assemble(gouraud_out, specular_out, diffuse_out=diffuse_out)
    if path not in ("jobs", "fused", "threads"):
        raise ValueError(f"path = {path!r} is out of range: legal values are {SHADER_PATHS}")
    a, k = jobs.divider_operands()
    q, _ = divider.divide_many(a, k, cfg.divider)
    di = jobs.increments(q, cfg)
    return fused.shade_jobs(jobs, di, offsets, cfg.gouraud, cfg.specular, threads=path == "threads")


def unit_shader(cfg: PipelineConfig, path: str = "fused"):
    """A rasteriser shader whose every pixel comes out of the bit-exact unit models (``path``:
    one of ``SHADER_PATHS``, the same image by each)."""
    if path not in SHADER_PATHS:
        raise ValueError(f"path = {path!r} is out of range: legal values are {SHADER_PATHS}")

    def shader(spans: Spans, ctx: ShadeContext) -> ShadeResult:
        rgb = None
        if path in ("fused", "threads") and cfg.brdf is None:
            intervals, spec, diff = span_routes(spans, ctx, cfg)
            rgb = fused.shade_spans(
                spans, spec, diff, ctx.material, ctx.lighting, cfg.divider, cfg.gouraud,
                cfg.specular, threads=path == "threads",
            )  # fmt: skip
        if rgb is None:  # the jobs' paths (and the units' errors, which they raise)
            jobs = build_jobs(spans, ctx, cfg)
            intervals, spec = jobs.intervals, np.zeros(len(spans), dtype=bool)
            spec[jobs.spec_span] = True
            diff = np.zeros(len(spans), dtype=bool)
            diff[jobs.diff_span] = True
            rgb = shade_pixels(jobs, spans.offsets, cfg, "units" if path == "units" else "jobs")
        channels = spans.g_start.shape[1]
        counters = route_counters(
            intervals, intervals[spec], np.repeat(intervals[diff], channels), channels, cfg
        )
        counters["triangles"] = int(np.count_nonzero(np.bincount(spans.tri)))
        counters["specular_triangles"] = int(np.count_nonzero(np.bincount(spans.tri[spec])))
        counters["diffuse_triangles"] = int(np.count_nonzero(np.bincount(spans.tri[diff])))
        return ShadeResult(rgb, counters=counters)

    return shader
