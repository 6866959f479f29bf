# SPDX-License-Identifier: Apache-2.0
"""The hybrid pipeline: batched kernels equal the units' public calls; methods; accuracy."""

from __future__ import annotations

import numpy as np
import pytest

from model.render import pipeline, raster, reference, scenefile
from model.render.pipeline import METHODS, PipelineConfig
from model.render.shade import ShadeContext, shade
from model.render.vectors import LightingParams
from model.study import metrics
from model.units import divider, gouraud, specular


@pytest.fixture(scope="module")
def sphere_raster() -> raster.Raster:
    return raster.rasterise(scenefile.builtin_scene("sphere", 64, 64))


def _object_jobs(r: raster.Raster, cfg: PipelineConfig):
    obj = r.objects[0]
    spans = obj.spans.select(obj.visible_per_span > 0)  # what shade sends a shader
    sc = r.scene
    ctx = ShadeContext(sc, 0, sc.objects[0].material, LightingParams.of(sc))
    return spans, ctx, pipeline.build_jobs(spans, ctx, cfg)


def test_batched_units_equal_the_public_per_line_calls(sphere_raster) -> None:
    """Every span, channel and pixel: the frame kernels = divide, shade_line, setup_line."""
    cfg = METHODS["hybrid"]
    spans, ctx, jobs = _object_jobs(sphere_raster, cfg)
    g_out, s_out = pipeline.run_units(jobs, spans.offsets, cfg)
    light = ctx.material.k_s * ctx.lighting.intensity
    checked = 0
    for s in range(len(spans)):
        lo, hi = spans.offsets[s], spans.offsets[s + 1]
        l_int = int(jobs.intervals[s])
        for c in range(3):
            a = int(jobs.i_end[s, c] - jobs.i_start[s, c])
            q = divider.divide(a, l_int, cfg.divider) if l_int else 0
            di = int(pipeline.increment_from_quotient(q, cfg)) if l_int else 0
            line = gouraud.shade_line(int(jobs.i_start[s, c]), di, l_int + 1, cfg.gouraud)
            np.testing.assert_array_equal(g_out[lo:hi, c], line)
        setup = specular.setup_line(
            spans.n_start[s], spans.n_end[s], spans.h_start[s], spans.h_end[s],
            ctx.material.n, light, l_int, cfg.specular,
        )  # fmt: skip
        spec = specular.shade_line(
            setup.c_reg, setup.dz_reg, setup.z0_reg, ctx.material.n, l_int, cfg.specular
        )
        np.testing.assert_array_equal(s_out[lo:hi], spec)
        checked += hi - lo
    assert checked == spans.n_pixels > 1000


def test_increment_rounding_and_range() -> None:
    cfg = PipelineConfig()
    n = cfg.divider.recip_bits
    q = np.array([0, (1 << (n - 1)) - 1, 1 << (n - 1), -(1 << (n - 1)), -(1 << (n - 1)) - 1])
    np.testing.assert_array_equal(pipeline.increment_from_quotient(q, cfg), [0, 0, 1, 0, -1])
    # The widest increments (a one-interval span from 0 to full scale and back) stay in format.
    lo, hi = cfg.gouraud.i0_range
    for a in (hi - lo, lo - hi):
        di = pipeline.increment_from_quotient(divider.divide(a, 1, cfg.divider), cfg)
        assert cfg.gouraud.di_range[0] <= di <= cfg.gouraud.di_range[1]
        assert di == a


def test_assemble_sums_and_saturates() -> None:
    g = np.array([[0, 100, 250], [255, 0, 10]])
    s = np.array([10, 200])
    np.testing.assert_array_equal(pipeline.assemble(g, s), [[10, 110, 255], [255, 200, 210]])


@pytest.mark.parametrize("name", ["sphere", "torus", "teapot", "quad"])
def test_hybrid_is_visually_identical_to_exact_blinn(name: str) -> None:
    """The thesis's criterion: NMSE <= 0.00025 against the accuracy reference (a)."""
    r = raster.rasterise(scenefile.builtin_scene(name, 128, 128))
    ref = shade(r, reference.exact_blinn).rgb
    hybrid = shade(r, pipeline.unit_shader(METHODS["hybrid"])).rgb
    assert metrics.nmse(hybrid, ref) <= metrics.NMSE_VISUALLY_IDENTICAL
    # The prototype's single cos^2 table and Gouraud-only are measurably worse.
    proto = shade(r, pipeline.unit_shader(METHODS["prototype"])).rgb
    gouraud_only = shade(r, pipeline.unit_shader(METHODS["gouraud"])).rgb
    assert metrics.nmse(proto, ref) > metrics.nmse(hybrid, ref)
    assert metrics.nmse(gouraud_only, ref) > metrics.nmse(hybrid, ref)


def test_adaptive_equals_hybrid_on_flagged_triangles_and_gouraud_elsewhere(sphere_raster) -> None:
    r = sphere_raster
    frames = {
        m: shade(r, pipeline.unit_shader(METHODS[m])) for m in ("hybrid", "gouraud", "adaptive")
    }
    flags = reference.object_highlight_flags(r.scene, obj=0, levels=0.5)
    tri = frames["adaptive"].tri_id
    covered = tri >= 0
    flagged = covered & flags[np.where(covered, tri, 0)]
    unflagged = covered & ~flagged
    assert flagged.sum() > 0 and unflagged.sum() > 0
    np.testing.assert_array_equal(frames["adaptive"].rgb[flagged], frames["hybrid"].rgb[flagged])
    np.testing.assert_array_equal(
        frames["adaptive"].rgb[unflagged], frames["gouraud"].rgb[unflagged]
    )
    counters = {m: f.stats.counters for m, f in frames.items()}
    assert counters["gouraud"]["specular_jobs"] == 0
    assert 0 < counters["adaptive"]["specular_jobs"] < counters["hybrid"]["specular_jobs"]
    assert counters["hybrid"]["specular_pixels"] == frames["hybrid"].stats.pixels_shaded


def test_counters_follow_the_units_cycle_counts(sphere_raster) -> None:
    cfg = METHODS["hybrid"]
    _, _, jobs = _object_jobs(sphere_raster, cfg)
    c = pipeline.unit_counters(jobs, cfg)
    _, k = jobs.divider_operands()
    assert c["divider_cycles"] == sum(divider.cycles(int(x)) + 1 for x in k)
    assert c["gouraud_cycles"] == 3 * sum(gouraud.cycles(int(x) + 1) + 1 for x in jobs.intervals)
    assert c["specular_cycles"] == sum(specular.cycles(int(x)) + 1 for x in jobs.intervals)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"specular_mode": "phong"}, r"specular_mode = 'phong' is out of range"),
        ({"divider": divider.DividerConfig(a_width=16)}, r"divider a_width = 16 is out of range"),
        (
            {"divider": divider.DividerConfig(k_width=8, recip_bits=20)},
            r"divider k_max = 255 and specular len_max = 2047 must reach",
        ),
        ({"highlight_levels": 0.0}, r"highlight_levels = 0.0 is out of range"),
    ],
)
def test_bad_pipeline_config(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        PipelineConfig(**kwargs)
