# SPDX-License-Identifier: Apache-2.0
"""The BRDF family's units in the pipeline (``PipelineConfig.brdf``, ``pipeline.BRDF_METHODS``):
many lines in one call (``brdf.lines.shade_lines``) equal the unit's line one by one, the
highlight jobs of a scene go through the unit the configuration names, the refusals name the
field, and a configuration file carries the unit (``[brdf]``)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from model.render import configfile, pipeline, raster, scenefile
from model.render.pipeline import BRDF_METHODS, METHODS, PipelineConfig
from model.render.shade import ShadeContext, shade
from model.render.vectors import LightingParams
from model.units import brdf, specular
from model.units.brdf import lines, unit

FORMS = list(unit.UNIT_CONFIGS)


@pytest.mark.parametrize("form", FORMS)
def test_many_lines_equal_the_unit_s_line_each(form: str) -> None:
    """Random lines (every n class: 0, 1, inside, 1000, 1001..1023; lengths 0..60, the longest)
    and the extremes of every operand, row by row against ``unit.unit_line``."""
    cfg = unit.UNIT_CONFIGS[form]
    a = cfg.angle
    rng = np.random.default_rng(7)
    rows = 300
    c = rng.integers(0, a.c_format.hi + 1, rows)
    dz = rng.integers(a.z_format.lo, a.z_format.hi + 1, rows) >> rng.integers(0, 20, rows)
    z0 = rng.integers(a.z_format.lo, a.z_format.hi + 1, rows)
    n = rng.choice([0, 1, 2, 8, 40, 999, 1000, 1001, 1023], rows)
    length = rng.integers(0, 61, rows)
    c[:4], z0[:4], dz[:4] = a.c_format.hi, [0, a.z_format.lo, a.z_format.hi, 0], 0
    length[-1], dz[-1], z0[-1] = a.len_max, a.z_format.hi, a.z_format.lo
    got = lines.shade_lines(c, dz, z0, n, length, cfg)
    for j in range(rows):
        want, _ = unit.unit_line(c[j], dz[j], z0[j], n[j], length[j], cfg)
        assert np.array_equal(got.line(j), want), (form, j, c[j], dz[j], z0[j], n[j], length[j])
    assert np.array_equal(got.cycles, unit.cycles(length, cfg))


def test_a_bad_row_is_named() -> None:
    cfg = unit.UNIT_CONFIGS[FORMS[0]]
    with pytest.raises(ValueError, match=r"c\[1\] = -1 is out of range"):
        lines.shade_lines([1, -1], [0, 0], [0, 0], [8, 8], [0, 0], cfg)
    with pytest.raises(ValueError, match="operand shapes are out of range"):
        lines.shade_lines([1], [0, 0], [0, 0], [8, 8], [0, 0], cfg)


@pytest.fixture(scope="module")
def sphere() -> raster.Raster:
    return raster.rasterise(scenefile.builtin_scene("sphere", 48, 48))


@pytest.mark.parametrize("form", FORMS)
def test_the_scene_s_highlight_jobs_go_through_the_brdf_unit(sphere, form: str) -> None:
    """Each highlight job's pixels are ``unit.unit_line`` of its registers, which are the
    patent unit's (``specular.setup_lines``); the Gouraud part is (c)'s; every shader path
    gives the same image."""
    cfg = BRDF_METHODS[form]
    obj = sphere.objects[0]
    spans = obj.spans.select(obj.visible_per_span > 0)
    sc = sphere.scene
    ctx = ShadeContext(sc, 0, sc.objects[0].material, LightingParams.of(sc))
    jobs = pipeline.build_jobs(spans, ctx, cfg)
    base = pipeline.build_jobs(spans, ctx, METHODS["hybrid"])
    assert np.array_equal(jobs.spec_dz, base.spec_dz) and np.array_equal(jobs.spec_c, base.spec_c)
    g_out, s_out, _ = pipeline.run_units(jobs, spans.offsets, cfg)
    g_base, _, _ = pipeline.run_units(base, spans.offsets, METHODS["hybrid"])
    assert np.array_equal(g_out, g_base)
    starts = spans.offsets[jobs.spec_span]
    for j in range(jobs.spec_span.size):
        length = int(jobs.intervals[jobs.spec_span[j]])
        want, _ = unit.unit_line(
            jobs.spec_c[j], jobs.spec_dz[j], jobs.spec_z0[j], jobs.spec_n[j], length, cfg.brdf
        )
        assert np.array_equal(s_out[starts[j] : starts[j] + length + 1], want), j
    assert s_out.any()
    frames = [shade(sphere, pipeline.unit_shader(cfg, p)).rgb for p in pipeline.SHADER_PATHS]
    assert all(np.array_equal(f, frames[0]) for f in frames)
    assert not np.array_equal(frames[0], shade(sphere, pipeline.unit_shader(METHODS["hybrid"])).rgb)
    counters = shade(sphere, pipeline.unit_shader(cfg)).stats.counters
    assert counters["specular_cycles"] == int(
        (unit.cycles(jobs.intervals[jobs.spec_span], cfg.brdf) + 1).sum()
    )


def test_bad_brdf_settings_are_refused_by_name() -> None:
    cfg = unit.UNIT_CONFIGS["quadratic"]
    with pytest.raises(ValueError, match="specular_mode = 'vertex' and diffuse_mode"):
        PipelineConfig(brdf=cfg, specular_mode="vertex")
    with pytest.raises(ValueError, match="diffuse_mode = 'unit'"):
        PipelineConfig(brdf=cfg, diffuse_mode="unit")
    with pytest.raises(ValueError, match="brdf angle out_width = 10 is out of range"):
        PipelineConfig(brdf=replace(cfg, angle=replace(specular.DEFAULT, out_width=10)))
    with pytest.raises(ValueError, match=r"coef_bits = 22 is out of range: legal widths are 11"):
        PipelineConfig(brdf=replace(brdf.CONFIGS["piecewise"], coef_bits=22))


def test_a_configuration_file_carries_the_brdf_unit(tmp_path: Path) -> None:
    for name, cfg in {**METHODS, **BRDF_METHODS}.items():
        path = configfile.write_config(cfg, tmp_path / f"{name}.toml")
        assert configfile.read_config(path) == cfg, name
        assert ("[brdf]" in path.read_text()) == (cfg.brdf is not None)
    bad = tmp_path / "bad.toml"
    bad.write_text('[brdf]\nform = "quadratic"\nwork_bits = 40\n')
    with pytest.raises(ValueError, match=r"bad.toml: \[brdf\] work_bits = 40 is out of range"):
        configfile.read_config(bad)
    bad.write_text('[brdf]\nform = "quadratic"\nangle = 1\n')
    with pytest.raises(ValueError, match=r"brdf.angle is not a field here"):
        configfile.read_config(bad)
