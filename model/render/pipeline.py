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
5. **Sum and saturate**: each channel is ``min(gouraud + specular, 255)``.

Every pixel value comes out of the unit models, through their batched public calls
(``divider.divide_many``, ``gouraud.shade_lines``, ``specular.shade_lines``: each row equals the
per-line call); the float work is only the set-up (1, 4).  The same steps run on RTL outputs in
the scene co-simulation (``sim/scene_cosim.py``): the jobs each unit receives are ``UnitJobs``
and the image is assembled from the units' outputs by ``assemble``, so the model image and the
RTL image differ only if a unit does.

Methods (``METHODS``): the hybrid with the patent's k-set and a = sqrt(n/k), the same with the
thesis's inflection-matched a, the prototype's single cos^2 table, Gouraud only (the specular
term evaluated at the vertices and interpolated with the diffuse one: no specular unit), and the
structure-adaptive method (the specular unit only on triangles the highlight test flags).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from model.render.reference import object_highlight_flags
from model.render.shade import ShadeContext, ShadeResult
from model.render.spans import Spans
from model.units import divider, gouraud, specular

SPECULAR_MODES = ("unit", "vertex", "adaptive")


@dataclass(frozen=True)
class PipelineConfig:
    """The units' configurations and how the specular term is made.

    ``specular_mode``: "unit" (every span through the specular unit), "vertex" (Gouraud only:
    specular at the vertices, interpolated by the Gouraud unit), "adaptive" (the unit on the
    triangles ``reference.object_highlight_flags`` marks at ``highlight_levels``, vertex
    specular elsewhere).
    """

    divider: divider.DividerConfig = divider.DEFAULT
    gouraud: gouraud.GouraudConfig = gouraud.DEFAULT
    specular: specular.SpecularConfig = specular.DEFAULT
    specular_mode: str = "unit"
    highlight_levels: float = 0.5

    def __post_init__(self) -> None:
        if self.specular_mode not in SPECULAR_MODES:
            raise ValueError(
                f"specular_mode = {self.specular_mode!r} is out of range: legal values are "
                f"{', '.join(SPECULAR_MODES)}"
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


METHODS: dict[str, PipelineConfig] = {
    "hybrid": PipelineConfig(),
    "inflection": PipelineConfig(specular=specular.INFLECTION),
    "prototype": PipelineConfig(specular=specular.PROTOTYPE),
    "gouraud": PipelineConfig(specular_mode="vertex"),
    "adaptive": PipelineConfig(specular_mode="adaptive"),
}


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
    """

    intervals: np.ndarray
    i_start: np.ndarray
    i_end: np.ndarray
    spec_span: np.ndarray
    spec_c: np.ndarray
    spec_dz: np.ndarray
    spec_z0: np.ndarray
    spec_n: np.ndarray
    counters: dict[str, int] = field(default_factory=dict)

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
    intervals = (spans.x_end - spans.x_start).astype(np.int64)
    if intervals.size and intervals.max() > cfg.gouraud.len_max - 1:
        raise ValueError(
            f"span of {int(intervals.max()) + 1} pixels is out of range: the units take lines of "
            f"1..{cfg.gouraud.len_max} pixels"
        )
    through_unit = _spans_through_specular_unit(spans, ctx, cfg)
    g_start, g_end = spans.g_start.copy(), spans.g_end.copy()
    # Without the unit, the specular term is evaluated at the vertices and interpolated with
    # the diffuse one (classic Gouraud): it joins every channel of the span-end intensities.
    vertex = ~through_unit
    g_start[vertex] += spans.s_start[vertex, None]
    g_end[vertex] += spans.s_end[vertex, None]
    spec_span = np.nonzero(through_unit)[0].astype(np.int64)
    regs = _specular_registers(spans, ctx, cfg, spec_span, intervals)
    return UnitJobs(
        intervals=intervals,
        i_start=quantise_intensity(g_start, cfg.gouraud),
        i_end=quantise_intensity(g_end, cfg.gouraud),
        spec_span=spec_span,
        spec_c=regs[0],
        spec_dz=regs[1],
        spec_z0=regs[2],
        spec_n=np.full(spec_span.size, ctx.material.n, dtype=np.int64),
    )


def _spans_through_specular_unit(spans: Spans, ctx: ShadeContext, cfg: PipelineConfig):
    if cfg.specular_mode == "unit":
        return np.ones(len(spans), dtype=bool)
    if cfg.specular_mode == "vertex":
        return np.zeros(len(spans), dtype=bool)
    # The host tests each triangle it draws once (not the hidden or culled ones).
    drawn, index = np.unique(spans.tri, return_inverse=True)
    flags = object_highlight_flags(
        ctx.scene, obj=ctx.obj, levels=cfg.highlight_levels, triangles=drawn
    )
    return flags[index]


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


def assemble(gouraud_out: np.ndarray, specular_out: np.ndarray, out_max: int = 255) -> np.ndarray:
    """Step 5: every channel = min(gouraud + specular, out_max), as uint8 pixels."""
    total = gouraud_out + specular_out[:, None]
    return np.minimum(total, out_max).astype(np.uint8)


def unit_counters(jobs: UnitJobs, cfg: PipelineConfig) -> dict[str, int]:
    """Hardware cost of the jobs, from the models' cycle counts (start-to-start clocks)."""
    _, k = jobs.divider_operands()
    channels = jobs.i_start.shape[1]
    spec_l = jobs.intervals[jobs.spec_span]
    return {
        "divider_jobs": int(k.size),
        "divider_cycles": int((divider.cycles(k, cfg.divider) + 1).sum()) if k.size else 0,
        "gouraud_jobs": int(jobs.intervals.size * channels),
        "gouraud_cycles": channels
        * int((gouraud.cycles(jobs.intervals + 1, cfg.gouraud) + 1).sum()),
        "specular_jobs": int(spec_l.size),
        "specular_pixels": int((spec_l + 1).sum()),
        "specular_cycles": int((specular.cycles(spec_l, cfg.specular) + 1).sum()),
    }


def run_units(jobs: UnitJobs, offsets: np.ndarray, cfg: PipelineConfig):
    """The model's outputs for the jobs: (gouraud (pixels, C), specular (pixels,)), span s at
    rows ``offsets[s] : offsets[s + 1]``; 0 on the spans that do not go through the specular
    unit.  Every value comes from the units' batched public calls."""
    a, k = jobs.divider_operands()
    q, _ = divider.divide_many(a, k, cfg.divider)
    di = jobs.increments(q, cfg)
    starts = offsets[:-1]
    g_out = np.zeros((int(offsets[-1]), jobs.i_start.shape[1]), dtype=np.int64)
    gouraud.shade_lines(jobs.i_start, di, jobs.intervals + 1, cfg.gouraud, out=g_out, at=starts)
    s_out = np.zeros(int(offsets[-1]), dtype=np.int64)
    specular.shade_lines(
        jobs.spec_c,
        jobs.spec_dz,
        jobs.spec_z0,
        jobs.spec_n,
        jobs.intervals[jobs.spec_span],
        cfg.specular,
        out=s_out,
        at=starts[jobs.spec_span],
    )
    return g_out, s_out


def unit_shader(cfg: PipelineConfig):
    """A rasteriser shader whose every pixel comes out of the bit-exact unit models."""

    def shader(spans: Spans, ctx: ShadeContext) -> ShadeResult:
        jobs = build_jobs(spans, ctx, cfg)
        gouraud_out, specular_out = run_units(jobs, spans.offsets, cfg)
        counters = unit_counters(jobs, cfg)
        counters["triangles"] = int(np.count_nonzero(np.bincount(spans.tri)))
        counters["specular_triangles"] = int(
            np.count_nonzero(np.bincount(spans.tri[jobs.spec_span]))
        )
        return ShadeResult(assemble(gouraud_out, specular_out), counters=counters)

    return shader
