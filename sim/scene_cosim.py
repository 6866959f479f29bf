# SPDX-License-Identifier: Apache-2.0
"""Scene co-simulation: every span of a scene through the three RTL units, vector mode.

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

Each unit's jobs become one stimulus (``job_stream``): three reset cycles, then every job's
operands written and started back to back (the next job's operands written in the start cycle,
the next start in the first cycle ``busy`` is 0), stepped through the protocol model
(sim/protocol.py) for every output of every cycle.  The plain Verilog vector bench
(sim/vectors/tb_<unit>.v, sim/vector_run.py; one build per configuration, cached) replays it
and compares every output in every cycle with that prediction, and writes the RTL's own result
words (``+OUT_FILE``); the image is assembled from those words, and it must equal the model's
image byte for byte (``tests/test_sim_scene.py``).  The simulator is the one SIM names: Icarus
(the default) or ``verilator`` (``verilator --binary``, which Verilator 5.006 runs).  The
specular unit runs beside the divider and Gouraud chain (threads; each simulator is a process).
"""

from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from model.hw.synth import synth_parameters
from model.render import pipeline, raster, scene, scenefile, shade
from model.render.pipeline import PipelineConfig, UnitJobs
from model.render.shade import ShadeContext
from model.render.spans import Spans
from sim import soak, units, vector_run
from sim.protocol import Job, ProtocolModel
from sim.runner import SIM_BUILD, hdl_parameters, simulator

# One vector-bench build per (simulator, configuration), reused by every later run.
BUILD_CACHE = SIM_BUILD / "vector_builds"


@dataclass
class CosimResult:
    rtl_rgb: np.ndarray
    model_rgb: np.ndarray
    pixels: int  # pixels shaded (sent through the units)
    sim: str = "icarus"
    jobs: dict[str, int] = field(default_factory=dict)  # jobs (starts) per unit
    results: dict[str, int] = field(default_factory=dict)  # RTL results per unit
    cycles: dict[str, int] = field(default_factory=dict)  # simulated clock cycles per unit
    seconds: dict[str, float] = field(default_factory=dict)  # wall time per unit, all steps
    # per unit and step (predict, write, build, simulate, parse), wall seconds
    steps: dict[str, dict[str, float]] = field(default_factory=dict)
    cached: dict[str, bool] = field(default_factory=dict)  # per unit: the build was reused
    wall_s: float = 0.0  # the whole co-simulation, rasterising and the model's image included

    @property
    def pixels_per_second(self) -> float:
        return self.pixels / max(self.wall_s, 1e-9)

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


def job_stream(
    cfg: units.UnitConfig, jobs: list[dict[str, int]]
) -> tuple[list[soak.Inputs], soak.Prediction, list[Job]]:
    """The stimulus that runs ``jobs`` back to back, its prediction and the started jobs.

    Three reset cycles, a cycle writing the first job's operands, then per job a start with the
    next job's operands written in the same cycle (they are for the next run) and idle cycles
    until the protocol model's ``busy`` falls: the next start comes in the first cycle busy is
    0, and the last job runs to its end."""
    spec = units.spec(cfg)
    model = ProtocolModel(spec, units.expect(cfg))
    held = {p.name: 0 for p in spec.operands}
    stim: list[soak.Inputs] = []
    outputs: list[dict[str, int | None]] = []
    pred_jobs: list[Job | None] = []
    result_jobs: list[Job | None] = []
    started: list[Job] = []

    def step(rst_n: int = 1, start: int = 0, write: dict[str, int] | None = None) -> None:
        inputs: soak.Inputs = {"rst_n": rst_n, "start": start}
        for p in spec.operands:
            we = write is not None
            if we:
                held[p.name] = int(write[p.name])  # type: ignore[index]
            inputs[f"{p.name}_we"] = int(we)
            inputs[f"{p.name}_in"] = held[p.name]
        stim.append(inputs)
        outputs.append(model.step(inputs))
        pred_jobs.append(model.last_job)
        result_jobs.append(model.result_job)

    for _ in range(3):
        step(rst_n=0)
    if jobs:
        step(write=jobs[0])
    for j in range(len(jobs)):
        step(start=1, write=jobs[j + 1] if j + 1 < len(jobs) else None)
        if model.last_job is None or model.stats.jobs_started != j + 1:
            raise AssertionError(f"job {j} was not accepted by the protocol model")
        started.append(model.last_job)
        while model.busy:
            step()
    return stim, soak.Prediction(outputs, pred_jobs, result_jobs, model.stats), started


def _replay(
    toplevel: str,
    config,
    params: dict,
    jobs: list[dict],
    name: str,
    sim: str,
    prebuilt: vector_run.Build | None = None,
) -> dict:
    """Run ``jobs`` through one RTL unit's vector bench under ``sim`` (built by ``prebuilt`` if
    given, else now or from the cache); return its results
    (``outputs``: per job the list of result dicts read from the RTL's own output words)."""
    began = time.perf_counter()
    folder = SIM_BUILD / name
    folder.mkdir(parents=True, exist_ok=True)
    spec = units.spec(config)
    steps: dict[str, float] = {}
    t0 = time.perf_counter()
    stim, pred, started = job_stream(config, jobs)
    steps["predict"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    # only the RESET_ALL = 0 instance is built (RESET_MODES = 1): the RESET_ALL = 1 pair of
    # each record is not read
    vectors = soak.write_vectors(spec, stim, pred.outputs, folder / "vectors.bin", pred.outputs)
    steps["write"] = time.perf_counter() - t0
    verilog = soak.verilog_parameters({**params, "RESET_MODES": 1})
    built = prebuilt or vector_run.build(toplevel, verilog, sim, BUILD_CACHE)
    steps["build"] = built.seconds
    if not built.ok:
        raise RuntimeError(f"{sim} could not build the vector bench of {toplevel}:\n{built.log}")
    out_file = folder / "outputs.hex"
    out_file.unlink(missing_ok=True)
    ran = vector_run.run(built, vectors, len(stim), out_file=out_file)
    steps["simulate"] = ran.wall_s
    if not ran.passed:
        raise AssertionError(
            f"{toplevel}: the RTL differs from the protocol model's prediction "
            f"({ran.mismatches} mismatches, exit {ran.returncode}):\n{ran.log[-4000:]}"
        )
    t0 = time.perf_counter()
    words = [int(w, 16) for w in out_file.read_text().split()]
    want = sum(len(job.results) for job in started)
    if len(words) != want or pred.stats.results_compared != want:
        raise AssertionError(f"{toplevel}: {len(words)} RTL results, the model expects {want}")
    of = soak.out_fields(spec)
    outputs, at = [], 0
    for job in started:
        outputs.append([soak.unpack(of, w) for w in words[at : at + len(job.results)]])
        at += len(job.results)
    steps["parse"] = time.perf_counter() - t0
    return {
        "outputs": outputs,
        "results": pred.stats.results_compared,
        "cycles": len(stim),
        "seconds": time.perf_counter() - began,
        "steps": steps,
        "cached": built.cached,
    }


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
    sim: str | None = None,
) -> CosimResult:
    """Render ``scene_name`` at ``size`` x ``size`` through the RTL units and through the model.

    ``scene_name`` is a built-in scene's name, or a ``scene.Scene`` (a scene file's or a mesh
    file's, ``scenefile.SceneSource.scene``), rendered at its own camera's size (``size`` is then
    unused).  ``method`` is one of ``pipeline.METHODS`` or any ``PipelineConfig`` (a fitted one:
    the ROM images it needs and the repository does not hold are written into
    ``sim_build/<tag>_roms/``).  ``sim``: ``icarus`` or ``verilator`` (None: as SIM says,
    ``sim.runner.simulator``)."""
    began = time.perf_counter()
    sim = sim or simulator()
    cfg = method if isinstance(method, PipelineConfig) else pipeline.METHODS[method]
    roms = SIM_BUILD / f"{tag}_roms"
    if isinstance(scene_name, scene.Scene):
        frame_scene = scene_name
    else:
        frame_scene = scenefile.builtin_scene(scene_name, size, size)
    frame_raster = raster.rasterise(frame_scene)
    objects = _collect_jobs(frame_raster, cfg)
    result = CosimResult(rtl_rgb=np.zeros(0), model_rgb=np.zeros(0), pixels=0, sim=sim)

    # 3. (first, beside 1 and 2) The specular unit: each object's highlight jobs, then its
    # diffuse jobs (n = 1).
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
    spec_params = synth_parameters("specular_unit", cfg.specular, roms)
    workers = ThreadPoolExecutor(max_workers=2 if (os.cpu_count() or 1) > 1 else 1)
    spec_future = workers.submit(
        _replay, "specular_unit", cfg.specular, spec_params, spec_jobs, f"{tag}_specular", sim
    )

    # 1. The divider: every division of the frame, objects in order.
    div_ops = [o.jobs.divider_operands() for o in objects.values()]
    div_jobs = [
        {"a": int(a), "k": int(k)}
        for a_arr, k_arr in div_ops
        for a, k in zip(a_arr, k_arr, strict=True)
    ]
    div_params = synth_parameters("divider_shift", cfg.divider, roms)
    gouraud_build = None
    if sim == "verilator":  # the Gouraud unit's build beside the divider's run
        gouraud_build = workers.submit(
            vector_run.build,
            "gouraud_segment",
            soak.verilog_parameters({**hdl_parameters(cfg.gouraud), "RESET_MODES": 1}),
            sim,
            BUILD_CACHE,
        )
    div = _replay("divider_shift", cfg.divider, div_params, div_jobs, f"{tag}_divider", sim)
    quotients = iter(out[0]["q"] for out in div["outputs"])

    # 2. The Gouraud unit, on increments made from the RTL's quotients.
    prebuilt = gouraud_build.result() if gouraud_build is not None else None
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
        sim,
        prebuilt,
    )
    gouraud_lines = iter(_gouraud_lines(gouraud["outputs"], cfg.gouraud.i_int))

    spec = spec_future.result()
    workers.shutdown()
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
        result.steps[unit] = run["steps"]
        result.cached[unit] = run["cached"]
    result.wall_s = time.perf_counter() - began
    return result
