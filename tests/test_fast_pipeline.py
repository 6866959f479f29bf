# SPDX-License-Identifier: Apache-2.0
"""The fast paths of the hybrid pipeline equal its reference path byte for byte.

The reference path is the units' batched public calls then ``assemble`` (``build_jobs`` +
``run_units`` + ``assemble``: ``unit_shader(cfg, "units")``); the fast paths are one kernel
per object from the spans (``"fused"``, the default), the same over threads (``"threads"``)
and ``build_jobs`` then one kernel for the units (``"jobs"``).  Every built-in
scene, every method of ``METHODS``, and configurations with narrow widths, P = 2 and 16 and a
fitted-like kept range of n.  No timing here: the speed is ``python -m model bench``'s.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from model.render import fused, pipeline, raster, scenefile
from model.render.pipeline import METHODS, PipelineConfig
from model.render.shade import shade
from model.units import divider, gouraud, specular
from model.units.gouraud.datapath import line_closed_kernel, line_kernel
from model.units.gouraud.network import network_arrays

SIZE = 64


@pytest.fixture(autouse=True)
def threads_on_small_images(monkeypatch) -> None:
    """The "threads" paths use the threads here, even on the small test images."""
    monkeypatch.setattr(fused, "THREAD_MIN_PIXELS", 0)


@pytest.fixture(scope="module")
def rasters(teapot_file) -> dict[str, raster.Raster]:
    return {
        name: raster.rasterise(scenefile.builtin_scene(name, SIZE, SIZE))
        for name in scenefile.SCENE_NAMES
    }


def first_difference(a: np.ndarray, b: np.ndarray) -> str | None:
    """Where two images differ (the first pixel, both values), or None if byte-identical."""
    if a.shape != b.shape or a.dtype != b.dtype:
        return f"shape/dtype {a.shape} {a.dtype} != {b.shape} {b.dtype}"
    diff = np.argwhere(a != b)
    if diff.size == 0:
        return None
    y, x = diff[0][:2]
    return f"{len(diff)} values differ, first at (y={y}, x={x}): {a[y, x]} != {b[y, x]}"


def assert_paths_equal(r: raster.Raster, cfg: PipelineConfig, label: str) -> None:
    ref = shade(r, pipeline.unit_shader(cfg, "units"))
    for path in ("fused", "threads", "jobs"):
        fast = shade(r, pipeline.unit_shader(cfg, path))
        assert first_difference(fast.rgb, ref.rgb) is None, (label, path)
        assert fast.stats.counters == ref.stats.counters, (label, path)
        np.testing.assert_array_equal(fast.tri_id, ref.tri_id)


@pytest.mark.parametrize("method", list(METHODS))
def test_fast_paths_equal_the_reference_path_on_every_scene(rasters, method: str) -> None:
    for name, r in rasters.items():
        assert_paths_equal(r, METHODS[method], f"{name} {method}")


def scene_n_range(r: raster.Raster) -> tuple[int, int]:
    ns = [o.material.n for o in r.scene.objects]
    return min(ns), max(ns)


def configs(r: raster.Raster) -> dict[str, PipelineConfig]:
    """A few configurations away from the default: narrow widths, P = 2 / 16, a kept n range."""
    n_lo, n_hi = scene_n_range(r)
    narrow_g = gouraud.GouraudConfig(i_frac=8, p=2, len_width=7)
    narrow_d = divider.DividerConfig(a_width=narrow_g.di_width, k_width=7, recip_bits=10)
    return {
        "narrow P=2": PipelineConfig(divider=narrow_d, gouraud=narrow_g, specular=specular.NARROW),
        "P=16 adaptive both": PipelineConfig(
            gouraud=gouraud.GouraudConfig(p=16),
            specular_mode="adaptive",
            diffuse_mode="adaptive",
            highlight_levels=2.0,
            diffuse_spread_deg=4.0,
        ),
        "fitted kept n": PipelineConfig(
            divider=narrow_d,
            gouraud=gouraud.GouraudConfig(i_frac=8, p=4, len_width=7),
            specular=replace(specular.NARROW, n_first=n_lo, n_last=n_hi),
        ),
        "diffuse unit narrow": PipelineConfig(
            divider=narrow_d,
            gouraud=narrow_g,
            specular=specular.NARROW,
            diffuse_mode="unit",
            specular_mode="vertex",
        ),
    }


@pytest.mark.parametrize("name", scenefile.SCENE_NAMES)
def test_fast_paths_equal_the_reference_path_for_other_configs(rasters, name: str) -> None:
    r = rasters[name]
    for label, cfg in configs(r).items():
        assert_paths_equal(r, cfg, f"{name} {label}")


def test_the_comparison_sees_one_lsb(rasters) -> None:
    """Deliberate error: one value one LSB off in one pixel is a difference."""
    frame = shade(rasters["teapot"], pipeline.unit_shader(METHODS["hybrid"]))
    bad = frame.rgb.copy()
    y, x = np.argwhere(frame.obj_id >= 0)[7]
    bad[y, x, 1] ^= 1
    assert first_difference(frame.rgb, frame.rgb) is None
    assert first_difference(bad, frame.rgb).startswith("1 values differ, first at")


@pytest.mark.parametrize("p", [2, 4, 8, 16])
def test_closed_form_gouraud_line_equals_the_network(p: int) -> None:
    """The fast path's Gouraud kernel = the unit's network kernel, random lines, any P."""
    cfg = gouraud.GouraudConfig(p=p, i_frac=6, len_width=9)
    rng = np.random.default_rng(p)
    net = network_arrays(cfg.network)
    values = np.empty((cfg.len_max // p + 1, p), dtype=np.int64)
    lanes, mult = np.empty_like(values), np.empty(p + 1, dtype=np.int64)
    for _ in range(300):
        length = int(rng.integers(1, cfg.len_max + 1))
        i0 = int(rng.integers(*cfg.i0_range, endpoint=True))
        di = int(rng.integers(*cfg.di_range, endpoint=True))
        a, b = np.empty(length, dtype=np.int64), np.empty(length, dtype=np.int64)
        bias, frac, hi = cfg.round_bias, cfg.i_frac, cfg.out_max
        line_kernel(i0, di, length, bias, frac, hi, *net, values, lanes, mult, a)
        line_closed_kernel(i0, di, length, bias, frac, hi, b)
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(a, gouraud.shade_line(i0, di, length, cfg))


def test_fused_refuses_an_operand_out_of_range(rasters) -> None:
    """The fast path checks the units' operand ranges as the batched calls do."""
    r = rasters["sphere"]
    obj = r.objects[0]
    spans = obj.spans.select(obj.visible_per_span > 0)
    from model.render.shade import ShadeContext
    from model.render.vectors import LightingParams

    sc = r.scene
    ctx = ShadeContext(sc, 0, sc.objects[0].material, LightingParams.of(sc))
    cfg = METHODS["hybrid"]
    jobs = pipeline.build_jobs(spans, ctx, cfg)
    di = np.zeros_like(jobs.i_start)
    jobs.spec_c[0] = cfg.specular.c_format.hi + 1
    with pytest.raises(ValueError, match="out of range"):
        fused.shade_jobs(jobs, di, spans.offsets, cfg.gouraud, cfg.specular)


def test_unknown_shader_path() -> None:
    with pytest.raises(ValueError, match="path = 'gpu' is out of range"):
        pipeline.unit_shader(METHODS["hybrid"], "gpu")


def _sphere_object(r: raster.Raster):
    from model.render.shade import ShadeContext
    from model.render.vectors import LightingParams

    obj = r.objects[0]
    spans = obj.spans.select(obj.visible_per_span > 0)
    sc = r.scene
    return spans, ShadeContext(sc, 0, sc.objects[0].material, LightingParams.of(sc))


@pytest.mark.parametrize("method", ["hybrid", "diffuse"])
def test_the_span_kernel_runs_and_equals_the_units(rasters, method: str) -> None:
    """``fused.shade_spans`` itself (no fallback) = build_jobs + run_units + assemble."""
    cfg = METHODS[method]
    spans, ctx = _sphere_object(rasters["sphere"])
    _, spec, diff = pipeline.span_routes(spans, ctx, cfg)
    rgb = fused.shade_spans(
        spans, spec, diff, ctx.material, ctx.lighting, cfg.divider, cfg.gouraud, cfg.specular
    )
    assert rgb is not None
    jobs = pipeline.build_jobs(spans, ctx, cfg)
    g_out, s_out, d_out = pipeline.run_units(jobs, spans.offsets, cfg)
    assert first_difference(rgb, pipeline.assemble(g_out, s_out, diffuse_out=d_out)) is None


def test_the_span_kernel_hands_a_bad_operand_to_the_reference_path(rasters) -> None:
    """A normal the set-up refuses: the kernel returns None, the shader raises the set-up's
    ``ValueError`` (from the reference path)."""
    cfg = METHODS["hybrid"]
    spans, ctx = _sphere_object(rasters["sphere"])
    n_start = spans.n_start.copy()
    n_start[3] = np.nan
    bad = replace(spans, n_start=n_start)
    _, spec, diff = pipeline.span_routes(bad, ctx, cfg)
    args = (ctx.material, ctx.lighting, cfg.divider, cfg.gouraud, cfg.specular)
    assert fused.shade_spans(bad, spec, diff, *args) is None
    with pytest.raises(ValueError, match="n1 is out of range"):
        pipeline.unit_shader(cfg)(bad, ctx)
