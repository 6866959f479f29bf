# SPDX-License-Identifier: Apache-2.0
"""Scene co-simulation: every span of a scene through the three RTL units under Icarus.

The rasteriser and the float set-up run in Python (the patent's external device).  The units'
work runs in RTL, in the order the data flows:

1. all divisions of the frame (a = I_end - I_start, k = l, per span and channel) through
   ``divider_shift``; the RTL's quotients become the Gouraud increments
   (``pipeline.increment_from_quotient``);
2. every (I_start, dI, l + 1) line through ``gouraud_segment``; the lanes its ``mask`` marks are
   the line's pixels;
3. every span's registers (C, dz, z0, n, l) through ``specular_unit``, and after each object's
   highlight jobs its diffuse jobs (methods with ``diffuse_mode`` "unit" or "adaptive": one per
   span and colour channel, ordinary jobs with n = 1);
4. ``pipeline.assemble`` sums and saturates, and the rasteriser's depth test writes the frame.

Each RTL run is a replay (``sim/tb_replay.py``): its protocol monitor still checks every result
against the model.  The image built from the RTL's outputs must equal the model's image byte for
byte (``tests/test_sim_scene.py``).
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from model.hw.synth import synth_parameters
from model.render import pipeline, raster, scene, scenefile, shade
from model.render.pipeline import PipelineConfig, UnitJobs
from model.render.shade import ShadeContext
from model.render.spans import Spans
from sim.runner import SIM_BUILD, hdl_parameters, run_bench


@dataclass
class CosimResult:
    rtl_rgb: np.ndarray
    model_rgb: np.ndarray
    pixels: int  # pixels shaded (sent through the units)
    jobs: dict[str, int] = field(default_factory=dict)  # jobs (starts) per unit
    results: dict[str, int] = field(default_factory=dict)  # RTL results per unit
    cycles: dict[str, int] = field(default_factory=dict)  # simulated clock cycles per unit
    seconds: dict[str, float] = field(default_factory=dict)  # wall time per unit run

    @property
    def pixels_per_second(self) -> float:
        return self.pixels / max(sum(self.seconds.values()), 1e-9)

    def sim_record(self, unit: str, test: str) -> dict:
        """The counts ``make sim``'s summary adds up (tests/conftest.py ``record_sim``)."""
        return {
            "unit": unit,
            "test": test,
            "jobs": sum(self.jobs.values()),
            "compared": sum(self.results.values()),
            "errors": 0,
            "cycles": sum(self.cycles.values()),
        }


@dataclass
class _ObjectJobs:
    offsets: np.ndarray
    jobs: UnitJobs


def _collect_jobs(frame_raster: raster.Raster, cfg: PipelineConfig) -> dict[int, _ObjectJobs]:
    """Pass 1: the jobs each object's spans send to the units (nothing is shaded)."""
    collected: dict[int, _ObjectJobs] = {}

    def record(spans: Spans, ctx: ShadeContext) -> np.ndarray:
        collected[ctx.obj] = _ObjectJobs(spans.offsets, pipeline.build_jobs(spans, ctx, cfg))
        return np.zeros((spans.n_pixels, 3), dtype=np.uint8)

    shade.shade(frame_raster, record)
    return collected


def _replay(toplevel: str, config, params: dict, jobs: list[dict], name: str) -> dict:
    """Run ``jobs`` through one RTL unit; return the replay bench's output file."""
    build = SIM_BUILD / name
    build.mkdir(parents=True, exist_ok=True)
    jobs_file, out_file = build / "jobs.json", build / "outputs.json"
    jobs_file.write_text(json.dumps({"jobs": jobs}))
    out_file.unlink(missing_ok=True)
    began = time.perf_counter()
    records = run_bench(
        toplevel,
        "sim.tb_replay",
        name,
        params,
        config,
        extra_env={"BENCH_JOBS": str(jobs_file), "BENCH_OUT": str(out_file)},
    )
    result = json.loads(Path(out_file).read_text())
    result["seconds"] = time.perf_counter() - began
    result["records"] = records
    return result


def _gouraud_lines(outputs: list[list[dict]], lane_bits: int) -> list[np.ndarray]:
    """Each job's pixels: the lanes of its segments that the mask marks, left to right."""
    lines = []
    for segments in outputs:
        pixels = []
        for seg in segments:
            word, mask = seg["pixels"], seg["mask"]
            lane = 0
            while mask >> lane:
                if (mask >> lane) & 1:
                    pixels.append((word >> (lane * lane_bits)) & ((1 << lane_bits) - 1))
                lane += 1
        lines.append(np.array(pixels, dtype=np.int64))
    return lines


def cosimulate(
    scene_name: str | scene.Scene = "sphere",
    size: int = 64,
    method: str | PipelineConfig = "hybrid",
    tag: str = "scene",
) -> CosimResult:
    """Render ``scene_name`` at ``size`` x ``size`` through the RTL units and through the model.

    ``scene_name`` is a built-in scene's name, or a ``scene.Scene`` (a scene file's or a mesh
    file's, ``scenefile.SceneSource.scene``), rendered at its own camera's size (``size`` is then
    unused).  ``method`` is one of ``pipeline.METHODS`` or any ``PipelineConfig`` (a fitted one:
    the ROM images it needs and the repository does not hold are written into
    ``sim_build/<tag>_roms/``)."""
    cfg = method if isinstance(method, PipelineConfig) else pipeline.METHODS[method]
    roms = SIM_BUILD / f"{tag}_roms"
    if isinstance(scene_name, scene.Scene):
        frame_scene = scene_name
    else:
        frame_scene = scenefile.builtin_scene(scene_name, size, size)
    frame_raster = raster.rasterise(frame_scene)
    objects = _collect_jobs(frame_raster, cfg)
    result = CosimResult(rtl_rgb=np.zeros(0), model_rgb=np.zeros(0), pixels=0)

    # 1. The divider: every division of the frame, objects in order.
    div_ops = [o.jobs.divider_operands() for o in objects.values()]
    div_jobs = [
        {"a": int(a), "k": int(k)}
        for a_arr, k_arr in div_ops
        for a, k in zip(a_arr, k_arr, strict=True)
    ]
    div_params = synth_parameters("divider_shift", cfg.divider, roms)
    div = _replay("divider_shift", cfg.divider, div_params, div_jobs, f"{tag}_divider")
    quotients = iter(out[0]["q"] for out in div["outputs"])

    # 2. The Gouraud unit, on increments made from the RTL's quotients.
    gouraud_jobs, increments = [], {}
    for obj, o in objects.items():
        n_div = o.jobs.divider_pairs[0].size
        q = np.array([next(quotients) for _ in range(n_div)], dtype=np.int64)
        di = o.jobs.increments(q, cfg)
        increments[obj] = di
        for s in range(o.jobs.intervals.size):
            for c in range(o.jobs.i_start.shape[1]):
                gouraud_jobs.append(
                    {
                        "i0": int(o.jobs.i_start[s, c]),
                        "di": int(di[s, c]),
                        "len": int(o.jobs.intervals[s]) + 1,
                    }
                )
    gouraud = _replay(
        "gouraud_segment",
        cfg.gouraud,
        hdl_parameters(cfg.gouraud),
        gouraud_jobs,
        f"{tag}_gouraud",
    )
    gouraud_lines = iter(_gouraud_lines(gouraud["outputs"], cfg.gouraud.i_int))

    # 3. The specular unit: each object's highlight jobs, then its diffuse jobs (n = 1).
    spec_jobs = []
    for o in objects.values():
        j = o.jobs
        for regs, spans in (
            ((j.spec_c, j.spec_dz, j.spec_z0, j.spec_n), j.spec_span),
            ((j.diff_c, j.diff_dz, j.diff_z0, j.diff_n), j.diff_span),
        ):
            spec_jobs += [
                {"c": int(c), "dz": int(dz), "z0": int(z0), "n": int(n), "len": int(l_int)}
                for c, dz, z0, n, l_int in zip(*regs, j.intervals[spans], strict=True)
            ]
    spec = _replay(
        "specular_unit",
        cfg.specular,
        synth_parameters("specular_unit", cfg.specular, roms),
        spec_jobs,
        f"{tag}_specular",
    )
    spec_lines = iter(np.array([r["intensity"] for r in out]) for out in spec["outputs"])

    # 4. Assemble per object from the RTL's outputs, in the order the jobs were sent.
    rtl_pixels: dict[int, np.ndarray] = {}
    for obj, o in objects.items():
        npix = int(o.offsets[-1])
        channels = o.jobs.i_start.shape[1]
        g_out = np.zeros((npix, channels), dtype=np.int64)
        for s in range(o.jobs.intervals.size):
            lo, hi = o.offsets[s], o.offsets[s + 1]
            for c in range(channels):
                g_out[lo:hi, c] = next(gouraud_lines)
        s_out = np.zeros(npix, dtype=np.int64)
        for s in o.jobs.spec_span:
            s_out[o.offsets[s] : o.offsets[s + 1]] = next(spec_lines)
        d_out = np.zeros((npix, channels), dtype=np.int64)
        for s, c in zip(o.jobs.diff_span, o.jobs.diff_channel, strict=True):
            d_out[o.offsets[s] : o.offsets[s + 1], c] = next(spec_lines)
        rtl_pixels[obj] = pipeline.assemble(g_out, s_out, diffuse_out=d_out)

    def replay_shader(spans: Spans, ctx: ShadeContext) -> np.ndarray:
        return rtl_pixels[ctx.obj]

    result.rtl_rgb = shade.shade(frame_raster, replay_shader).rgb
    model_frame = shade.shade(frame_raster, pipeline.unit_shader(cfg))
    result.model_rgb = model_frame.rgb
    result.pixels = model_frame.stats.pixels_shaded
    for unit, run in (
        ("divider_shift", div),
        ("gouraud_segment", gouraud),
        ("specular_unit", spec),
    ):
        result.jobs[unit] = len(run["outputs"])
        result.results[unit] = run["results"]
        result.cycles[unit] = run["cycles"]
        result.seconds[unit] = run["seconds"]
    return result
