# SPDX-License-Identifier: Apache-2.0
"""What a scene asks of the units: every n, every span length, the ranges each unit sees.

Owns ``SceneNeeds`` (the figures) and ``analyse`` (a rasterised scene to its needs).  The figures
come from the operands the pipeline would send the units (``pipeline.build_jobs`` with every span
through the specular unit and the default, widest configuration), so they are what the hardware
sees, not an estimate from the geometry.  May import numpy and ``model.render`` and
``model.units``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from model.render import pipeline, raster, shade
from model.units import specular


@dataclass(frozen=True)
class SceneNeeds:
    """The operands a scene sends the units (hidden spans skipped, as ``shade`` does)."""

    n_values: tuple[int, ...]  # the materials' exponents with a shaded span
    objects: int
    triangles_shaded: int
    spans: int
    pixels: int
    longest_span: int  # pixels; a span of l + 1 pixels has l intervals
    span_histogram: tuple[tuple[int, int], ...]  # (bits needed for l, spans), l = intervals
    z_abs_max: float  # largest |zeta| the specular accumulator reaches, units of pi/2
    dz_abs_max: float  # largest |dz|, units of pi/2
    c_max: float  # largest specular C register, output levels
    intensity_min: float  # Gouraud span-end intensities, levels
    intensity_max: float
    dividend_abs_max: int  # largest |I_end - I_start| the divider gets, Q8.f register units
    divisor_max: int  # largest k (intervals) the divider gets

    @property
    def len_bits(self) -> int:
        """Bits of an interval counter that holds the longest span's intervals (at least 1)."""
        return max(1, (self.longest_span - 1).bit_length())

    def as_dict(self) -> dict:
        return asdict(self)

    def summary(self) -> list[str]:
        """The lines ``shading fit`` prints about the scene."""
        return [
            f"n values: {', '.join(map(str, self.n_values)) or 'none'} "
            f"({self.objects} objects, {self.triangles_shaded} triangles shaded)",
            f"spans: {self.spans}, {self.pixels} pixels, longest {self.longest_span} pixels "
            f"({self.longest_span - 1} intervals: {self.len_bits} bits)",
            f"specular: |zeta| <= {self.z_abs_max:.4f} x pi/2, |dz| <= {self.dz_abs_max:.5f} "
            f"x pi/2, C <= {self.c_max:.2f} levels",
            f"Gouraud: span-end intensities {self.intensity_min:.2f}..{self.intensity_max:.2f} "
            f"levels; divider: |a| <= {self.dividend_abs_max}, k <= {self.divisor_max}",
        ]


def analyse(frame_raster: raster.Raster) -> SceneNeeds:
    """The needs of the scene ``frame_raster`` was made from (one pass, nothing is shaded)."""
    cfg = pipeline.PipelineConfig()
    spec = cfg.specular
    found: dict[str, list] = {
        k: [] for k in ("n", "intervals", "z", "dz", "c", "i_start", "i_end", "a", "k")
    }

    def analysing_shader(spans, ctx: shade.ShadeContext) -> np.ndarray:
        jobs = pipeline.build_jobs(spans, ctx, cfg)
        ends = jobs.spec_z0 + jobs.intervals[jobs.spec_span] * jobs.spec_dz
        found["n"].append(ctx.material.n)
        found["intervals"].append(jobs.intervals)
        found["z"].append(np.maximum(np.abs(jobs.spec_z0), np.abs(ends)))
        found["dz"].append(np.abs(jobs.spec_dz))
        found["c"].append(jobs.spec_c)
        found["i_start"].append(jobs.i_start.ravel())
        found["i_end"].append(jobs.i_end.ravel())
        a, k = jobs.divider_operands()
        found["a"].append(np.abs(a))
        found["k"].append(k)
        return np.zeros((spans.n_pixels, 3), dtype=np.uint8)

    frame = shade.shade(frame_raster, analysing_shader)
    stats = frame.stats

    def cat(key: str) -> np.ndarray:
        return np.concatenate(found[key]) if found[key] else np.zeros(0, dtype=np.int64)

    def top(key: str, scale: float = 1.0) -> float:
        values = cat(key)
        return float(values.max()) * scale if values.size else 0.0

    intervals = cat("intervals")
    bits = np.array([int(v).bit_length() for v in intervals], dtype=np.int64)
    hist = tuple(
        (int(b), int(c)) for b, c in zip(*np.unique(bits, return_counts=True), strict=True)
    )
    intensities = np.concatenate([cat("i_start"), cat("i_end")])
    i_scale = 2.0**-cfg.gouraud.i_frac
    z_scale = 2.0**-spec.z_frac_bits
    return SceneNeeds(
        n_values=stats.n_values,
        objects=len(found["n"]),
        triangles_shaded=stats.triangles_shaded,
        spans=stats.spans_shaded,
        pixels=stats.pixels_shaded,
        longest_span=stats.longest_span,
        span_histogram=hist,
        z_abs_max=top("z", z_scale),
        dz_abs_max=top("dz", z_scale),
        c_max=top("c", 2.0**-spec.c_frac_bits),
        intensity_min=float(intensities.min()) * i_scale if intensities.size else 0.0,
        intensity_max=float(intensities.max()) * i_scale if intensities.size else 0.0,
        dividend_abs_max=int(top("a")),
        divisor_max=int(top("k")),
    )


def needs_ks(needs: SceneNeeds) -> tuple[int, ...]:
    """The patent decoder's k for every n the scene uses (sorted, distinct)."""
    return tuple(sorted({specular.decode_k(n) for n in needs.n_values}))
