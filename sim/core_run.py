# SPDX-License-Identifier: Apache-2.0
"""The shading core's stream bench (``sim/vectors/tb_shading_core.v``): build it under Icarus
or ``verilator --binary`` from ``rtl/shading_core.f``, run span beats through it with random
input idles and output stalls, and compare every pixel beat with the model of the core
(``model.render.core.core_pixels``).  A mismatch names the pixel, what the RTL gave, what the
model gives and the span beat that reproduces it."""

from __future__ import annotations

import hashlib
import math
import os
import re
import shutil
import subprocess
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

from model.hw.sources import source_list
from model.hw.synth import synth_parameters
from model.render import core
from model.render.pipeline import BRDF_METHODS, METHODS, PipelineConfig
from model.units import brdf, divider, gouraud, specular
from sim import vector_run
from sim.runner import SIM_BUILD, object_cache

BENCH = vector_run.VECTOR_DIR / "tb_shading_core.v"
BUILDS = SIM_BUILD / "core_builds"
DONE = re.compile(
    r"DONE spans=(\d+) pixels=(\d+) first_in=(-?\d+) last_out=(-?\d+) cycles=(-?\d+) "
    r"stalls=(\d+) errors=(\d+)"
)


@dataclass
class CoreRun:
    """One run of span beats through the core's RTL."""

    spans: int
    pixels: int
    cycles: int  # clocks from the first span beat taken to the last pixel beat, inclusive
    stalls: int  # clocks a pixel beat waited for tready
    protocol_errors: int
    mismatches: list[str] = field(default_factory=list)
    build_s: float = 0.0
    run_s: float = 0.0
    beats: list[tuple[int, int, int]] = field(default_factory=list)  # (tdata, tlast, tuser)

    @property
    def px_per_clock(self) -> float:
        return self.pixels / max(self.cycles, 1)


def parameters(cfg: PipelineConfig, rom_dir: Path | None = None, **kw) -> dict[str, object]:
    """``core.core_parameters`` with every ROM image on disk (a fitted configuration's images
    are generated into ``rom_dir``, as ``model.hw.synth.synth_parameters`` does per unit)."""
    params = core.core_parameters(cfg, **kw)
    params["RECIP_ROM_FILE"] = synth_parameters("divider_shift", cfg.divider, rom_dir)["ROM_FILE"]
    spec = synth_parameters("specular_unit", cfg.specular, rom_dir)
    params["A_ROM_FILE"], params["COS_ROM_FILE"] = spec["A_ROM_FILE"], spec["COS_ROM_FILE"]
    if cfg.brdf is not None:
        own = synth_parameters("brdf_unit", cfg.brdf, rom_dir)
        for name in ("ANGLE_ROM_FILE", "COEF_ROM_FILE", "LOG_ROM_FILE"):
            if name in params:
                params[name] = own[name]
    return params


def method_config(method: str | PipelineConfig) -> PipelineConfig:
    """A method's pipeline configuration: a name of ``pipeline.METHODS`` or of
    ``pipeline.BRDF_METHODS`` (the hybrid with the highlight through a BRDF form), or a
    ``PipelineConfig`` itself."""
    if isinstance(method, PipelineConfig):
        return method
    known = {**METHODS, **BRDF_METHODS}
    if method not in known:
        raise ValueError(f"method = {method!r} is out of range: legal are {', '.join(known)}")
    return known[method]


def _verilog(params: dict[str, object]) -> dict[str, str]:
    return {k: (f'"{v}"' if isinstance(v, str) else str(int(v))) for k, v in params.items()}


def build(
    params: dict[str, object], sim: str = "icarus", rtl: list[Path] | None = None
) -> tuple[list[str], Path, float]:
    """(command, folder, seconds) of the built bench for ``params`` (cached by content);
    ``rtl``: the core's sources (default: what ``rtl/shading_core.f`` lists)."""
    if sim not in vector_run.SIMS:
        raise ValueError(f"sim = {sim!r} is out of range: legal values are {vector_run.SIMS}")
    sources = [BENCH, *(rtl or source_list("shading_core"))]
    verilog = _verilog(params)
    common = [f'-DSHADING_ROM_DIR="{vector_run.RTL_DIR / "rom"}"']
    digest = hashlib.sha256(vector_run.tool_version(sim).encode())
    for path in sources:
        digest.update(path.read_bytes())
    digest.update(repr((sorted(verilog.items()), vector_run.VERILATOR_FLAGS)).encode())
    folder = BUILDS / f"{sim}_{digest.hexdigest()[:16]}"
    top = "tb_shading_core"
    if sim == "icarus":
        exe = folder / f"{top}.vvp"
        cmd = ["iverilog", "-g2005", "-o", str(exe), "-s", top, *common]
        cmd += [f"-P{top}.{k}={v}" for k, v in verilog.items()] + [str(s) for s in sources]
        command = ["vvp", "-n", str(exe)]
    else:
        exe = folder / "obj" / f"V{top}"
        cmd = ["verilator", "--binary", *vector_run.VERILATOR_FLAGS, "--top-module", top]
        cmd += ["-Mdir", str(folder / "obj"), *common]
        cmd += [f"-G{k}={v}" for k, v in verilog.items()] + [str(s) for s in sources]
        command = [str(exe)]
    if (folder / "built.ok").exists() and exe.exists():
        return command, folder, 0.0
    # built in a folder of this process's own, then renamed: parallel runs never share one
    work = folder.with_name(f"{folder.name}.{os.getpid()}.tmp")
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    cmd = [str(work / Path(a).relative_to(folder)) if a.startswith(str(folder)) else a
           for a in cmd]  # fmt: skip
    t0 = time.monotonic()
    env = {**os.environ, **object_cache()}  # ccache for verilator --binary's compiles
    made = subprocess.run(cmd, capture_output=True, text=True, cwd=work, timeout=3600, env=env)
    if made.returncode != 0:
        shutil.rmtree(work, ignore_errors=True)
        raise RuntimeError(f"{sim} could not build the core's bench:\n{made.stdout}{made.stderr}")
    (work / "built.ok").write_text(" ".join(cmd) + "\n")
    try:
        work.rename(folder)
    except OSError:  # another process published the same build first: use that one
        shutil.rmtree(work, ignore_errors=True)
    return command, folder, time.monotonic() - t0


def run_words(
    words: list[int],
    fmt: core.SpanFormat,
    params: dict[str, object],
    sim: str = "icarus",
    idle_pct: int = 0,
    stall_pct: int = 0,
    seed: int = 1,
    tag: str = "core",
    rtl: list[Path] | None = None,
) -> CoreRun:
    """Span beats ``words`` through the core's RTL; every pixel beat compared with
    ``core.core_pixels`` of the same words."""
    if not words:
        raise ValueError("words is empty: the core's bench needs at least one span beat")
    want = core.core_pixels(words, fmt, bool(params["SPECULAR"]), bool(params["DIFFUSE"]))
    command, folder, build_s = build(params, sim, rtl)
    work = SIM_BUILD / f"{tag}_{os.getpid()}"  # one folder per process: xdist runs side by side
    work.mkdir(parents=True, exist_ok=True)
    span_file, out_file = work / "spans.hex", work / "pixels.hex"
    digits = -(-fmt.width // 4)
    span_file.write_text("".join(f"{w:0{digits}x}\n" for w in words))
    out_file.unlink(missing_ok=True)
    args = [
        f"+SPAN_FILE={span_file}", f"+OUT_FILE={out_file}", f"+SPANS={len(words)}",
        f"+PIXELS={len(want)}", f"+IDLE_PCT={idle_pct}", f"+STALL_PCT={stall_pct}",
        f"+SEED={seed}", f"+MAX_CYCLES={40 * len(want) + 10000}",
    ]  # fmt: skip
    t0 = time.monotonic()
    ran = subprocess.run([*command, *args], capture_output=True, text=True, cwd=folder,
                         timeout=3600)  # fmt: skip
    run_s = time.monotonic() - t0
    log = ran.stdout + ran.stderr
    done = DONE.search(log)
    if ran.returncode != 0 or done is None:
        raise AssertionError(f"the core's bench did not finish (exit {ran.returncode}):\n{log}")
    beats = []
    for line in out_file.read_text().split("\n"):
        if line.strip():
            d, last, user = line.split()
            beats.append((int(d, 16), int(last, 16), int(user, 16)))
    result = CoreRun(
        spans=int(done.group(1)),
        pixels=int(done.group(2)),
        cycles=int(done.group(5)),
        stalls=int(done.group(6)),
        protocol_errors=int(done.group(7)),
        build_s=build_s,
        run_s=run_s,
        beats=beats,
    )
    result.mismatches = compare(beats, want, words, fmt)
    if result.protocol_errors:
        result.mismatches.insert(0, f"{result.protocol_errors} AXI4-Stream rule violations:\n{log}")
    return result


def compare(
    beats: list[tuple[int, int, int]], want: list[dict[str, int]], words: list[int],
    fmt: core.SpanFormat,
) -> list[str]:  # fmt: skip
    """Every difference between the RTL's beats and the model's pixels, each with the span
    beat that reproduces it (the first 20)."""
    pix = core.PixelFormat(fmt.x_width, fmt.y_width)
    layout = pix.layout()
    span_of = [s for s, w in enumerate(words)
               for _ in range(core.unpack(fmt.layout(), w)["l"] + 1)]  # fmt: skip
    out = []
    if len(beats) != len(want):
        out.append(f"the RTL gave {len(beats)} pixel beats, the model {len(want)}")
    for i, (got, exp) in enumerate(zip(beats, want, strict=False)):
        g = {**core.unpack(layout, got[0]), "last": got[1], "n_err": got[2]}
        if g != exp:
            s = span_of[i]
            out.append(
                f"pixel {i} (span {s}): RTL {g}, model {exp}; span beat 0x{words[s]:x} = "
                f"{core.unpack(fmt.layout(), words[s])}"
            )
            if len(out) >= 20:
                break
    return out


@dataclass
class FrameResult:
    """A frame through the core's RTL and through the model."""

    rtl_rgb: object
    model_rgb: object
    run: CoreRun
    model_cycles: int  # core.core_cycles of the frame's pixels

    @property
    def equal(self) -> bool:
        import numpy as np

        return bool(np.array_equal(self.rtl_rgb, self.model_rgb))


def cosimulate(
    scene_name="sphere", size: int = 64, method: str | PipelineConfig = "hybrid",
    sim: str = "icarus", idle_pct: int = 0, stall_pct: int = 0, seed: int = 1,
    tag: str = "core_scene",
) -> FrameResult:  # fmt: skip
    """Render a scene through the core's RTL: the frame's span beats in, the pixel beats out,
    the frame assembled from them by the rasteriser's depth test; and through the model
    (``pipeline.unit_shader``).  ``scene_name``: a built-in scene's name or a ``scene.Scene``."""
    import numpy as np

    from model.render import pipeline, raster, scene, scenefile, shade

    cfg = method_config(method)
    if isinstance(scene_name, scene.Scene):
        frame_scene = scene_name
    else:
        frame_scene = scenefile.builtin_scene(scene_name, size, size)
    frame_raster = raster.rasterise(frame_scene)
    fmt = core.SpanFormat(cfg)
    stream = core.frame_stream(frame_raster, cfg, fmt)
    params = parameters(cfg, SIM_BUILD / f"{tag}_roms")
    result = run_words(stream.words, fmt, params, sim, idle_pct, stall_pct, seed, tag)
    if result.mismatches:
        raise AssertionError("the core's RTL differs from its model:\n" + "\n".join(
            result.mismatches))  # fmt: skip
    layout = core.PixelFormat(fmt.x_width, fmt.y_width).layout()
    rgb = np.array([[core.unpack(layout, b[0])[k] for k in ("r", "g", "b")]
                    for b in result.beats], dtype=np.uint8).reshape(-1, 3)  # fmt: skip
    per_object, at = {}, 0
    for obj, n in zip(stream.objects, stream.pixels, strict=True):
        per_object[obj] = rgb[at : at + n]
        at += n

    def replay(spans, ctx):
        return per_object[ctx.obj]

    rtl_rgb = shade.shade(frame_raster, replay).rgb
    model_rgb = shade.shade(frame_raster, pipeline.unit_shader(cfg)).rgb
    model_cycles = core.core_cycles(stream.total_pixels, cfg, bool(params["SPECULAR"]))
    return FrameResult(rtl_rgb, model_rgb, result, model_cycles)


def shipped_configs() -> dict[str, PipelineConfig]:
    """The core configurations users ship besides the default, which the stream bench runs
    (tests/test_core.py) and make coverage measures: narrow widths (4-bit Gouraud levels and
    4-bit highlights, the sum's width at its smallest), the kept range of n (N_FIRST > 1, as
    shading fit emits; no diffuse path), the UP5K tables, and the highlight through each BRDF
    form with a pipe in the core at its default widths (``BRDF_METHODS``: "brdf_<form>")."""
    return {
        "narrow": PipelineConfig(
            divider=divider.DividerConfig(a_width=9, k_width=7, recip_bits=8),
            gouraud=gouraud.GouraudConfig(i_int=4, i_frac=4, p=2, len_width=7),
            specular=replace(specular.NARROW, out_width=4),
            diffuse_mode="unit",
        ),
        "kept": PipelineConfig(
            divider=divider.DividerConfig(a_width=13, k_width=7, recip_bits=8),
            gouraud=gouraud.GouraudConfig(i_int=8, i_frac=4, p=2, len_width=7),
            specular=specular.KEPT,
        ),
        "up5k": PipelineConfig(specular=specular.UP5K, diffuse_mode="unit"),
        **{f"brdf_{form}": BRDF_METHODS[form] for form in core.CORE_FORMS},
    }


VECTOR_SET = vector_run.VECTOR_DIR / "core_default"
"""The committed vector set of the default core: span beats and the model's pixel beats."""
VECTOR_SPANS = 300
VECTOR_SEED = 2026


def vector_set_words(cfg: PipelineConfig | None = None) -> list[int]:
    """The committed set's span beats: ``VECTOR_SPANS`` random spans (``random_spans``), every
    field in its range, the longest span and one-pixel spans among them."""
    cfg = cfg or METHODS["diffuse"]
    fmt = core.SpanFormat(cfg)
    import numpy as np

    rng = np.random.default_rng(VECTOR_SEED)
    lengths = rng.integers(1, 16, VECTOR_SPANS)
    lengths[:20] = 1
    lengths[100] = cfg.gouraud.len_max
    return random_spans(fmt, lengths, VECTOR_SEED)


def random_spans(fmt: core.SpanFormat, lengths, seed: int, lit: float = 0.0) -> list[int]:
    """Span beats of ``lengths`` pixels, every other field random in its range (n from 0 to
    1023: the refused ones included).  ``lit``: the share of spans whose highlight is lit
    (spec set, n log-uniform over 1..1000, z0 within the width of cos^n, pi/2 / sqrt(n), of the
    highlight's centre, dz small enough that most of the span stays there: the highlight's
    value in most pixels, and neighbouring spans of different n, which a random angle, mostly
    beyond pi/2, leaves dark); 0 draws the same beats as before it was added.  With the
    piecewise form's highlight half the lit spans reach as far as its bloom part shines (where
    c / (alpha - beta c) falls to 2^-8, many times that width): the cubic's pixels inside the
    junction, the divider's beyond it, and spans across it."""
    import numpy as np

    rng = np.random.default_rng(seed)
    g, s = fmt.cfg.gouraud, fmt.cfg.specular
    z_lo, z_hi = s.z_format.lo, s.z_format.hi
    half_pi = 1 << s.z_frac_bits
    bloom_form = fmt.cfg.brdf is not None and fmt.cfg.brdf.form == "piecewise"
    layout = fmt.layout()
    words = []
    for n_px in (int(v) for v in lengths):
        row = {
            "x": int(rng.integers(0, (1 << fmt.x_width) - n_px + 1)),
            "y": int(rng.integers(0, 1 << fmt.y_width)),
            "l": n_px - 1,
            "spec": int(rng.integers(0, 2)),
            "diff": int(rng.integers(0, 2)),
            "c": int(rng.integers(0, 1 << s.c_width)),
            "dz": int(rng.integers(z_lo, z_hi + 1) >> int(rng.integers(0, 16))),
            "z0": int(rng.integers(z_lo, z_hi + 1)),
            "n": int(rng.integers(0, 1 << core.N_WIDTH)),
            "diff_dz": int(rng.integers(z_lo, z_hi + 1) >> int(rng.integers(0, 16))),
            "diff_z0": int(rng.integers(z_lo, z_hi + 1)),
        }
        for c in range(core.CHANNELS):
            row[f"i_start{c}"] = int(rng.integers(0, 1 << g.i_width))
            row[f"i_end{c}"] = int(rng.integers(0, 1 << g.i_width))
            row[f"diff_c{c}"] = int(rng.integers(0, 1 << s.c_width))
        if lit and rng.random() < lit:
            n = int(np.clip(round(1000.0 ** rng.random()), 1, 1000))
            width = int(half_pi / np.sqrt(n))  # cos^n falls to about e^-1.2 there
            if bloom_form and rng.random() < 0.5:
                bloom, level = brdf.bloom_coefficients(n), 2.0**-8
                reach = math.acos(level * bloom.alpha / (1.0 + level * bloom.beta))
                width = max(width, int(half_pi * min(1.0, reach / (math.pi / 2))))
            reach = int(rng.integers(-width, width + 1)) // max(n_px - 1, 1)
            row.update(
                spec=1,
                z0=int(rng.integers(-width, width + 1)),
                dz=max(z_lo, min(z_hi, reach >> int(rng.integers(0, 4)))),
                n=n,
            )
        words.append(core.pack(layout, row))
    return words


def vector_set_text(cfg: PipelineConfig | None = None) -> tuple[str, str]:
    """(spans.hex, pixels.hex) of the committed set: the span beats and the model's beats."""
    cfg = cfg or METHODS["diffuse"]
    fmt = core.SpanFormat(cfg)
    pix = core.PixelFormat(fmt.x_width, fmt.y_width)
    words = vector_set_words(cfg)
    digits, pdigits = -(-fmt.width // 4), -(-pix.width // 4)
    spans = "".join(f"{w:0{digits}x}\n" for w in words)
    pixels = "".join(
        f"{core.pixel_word(p, pix):0{pdigits}x} {p['last']:x} {p['n_err']:x}\n"
        for p in core.core_pixels(words, fmt)
    )
    return spans, pixels


def write_vector_set(folder: Path = VECTOR_SET) -> None:
    """Write the committed set (``make vectors``)."""
    spans, pixels = vector_set_text()
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "spans.hex").write_text(spans)
    (folder / "pixels.hex").write_text(pixels)
    print(f"wrote {folder}: {spans.count(chr(10))} span beats, {pixels.count(chr(10))} pixel beats")


if __name__ == "__main__":
    write_vector_set()


@dataclass
class SetupRate:
    """The host's side: span beats a frame needs and how fast the model's set-up makes them."""

    spans: int
    pixels: int
    seconds: float  # best of the timed runs: rasterised spans to packed span beats
    setup_seconds: float  # of which pipeline.build_jobs (the float set-up, quantised)

    @property
    def spans_per_second(self) -> float:
        return self.spans / max(self.seconds, 1e-12)

    def needed_per_second(self, px_per_clock: float, fmax_mhz: float) -> float:
        """Span beats per second that keep the core at ``px_per_clock`` at ``fmax_mhz``."""
        return px_per_clock * fmax_mhz * 1e6 * self.spans / max(self.pixels, 1)


def setup_rate(scene_name="teapot", size: int = 256, method="hybrid", repeats: int = 3):
    """Time the model's per-span set-up on one CPU core (numba's threads set to one): every
    object's spans through ``pipeline.build_jobs`` (the float set-up and quantisation) and
    ``core.span_beats`` (packing), the rasterising left out; best of ``repeats`` after one
    warm-up run.  ``scene_name``: a built-in scene's name or a ``scene.Scene``."""
    import numba

    from model.render import pipeline, raster, scene, scenefile, shade

    cfg = method_config(method)
    if isinstance(scene_name, scene.Scene):
        frame = raster.rasterise(scene_name)
    else:
        frame = raster.rasterise(scenefile.builtin_scene(scene_name, size, size))
    fmt = core.SpanFormat(cfg)
    collected = []

    def record(spans, ctx):
        collected.append((spans, ctx))
        return __import__("numpy").zeros((spans.n_pixels, core.CHANNELS), dtype="uint8")

    shade.shade(frame, record)
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        best, best_setup = float("inf"), float("inf")
        for run in range(repeats + 1):
            t0 = time.perf_counter()
            count, setup = 0, 0.0
            for spans, ctx in collected:
                t1 = time.perf_counter()
                jobs = pipeline.build_jobs(spans, ctx, cfg)
                setup += time.perf_counter() - t1
                count += len(core.span_beats(jobs, spans.x_start, spans.y, fmt))
            if run:
                best = min(best, time.perf_counter() - t0)
                best_setup = min(best_setup, setup)
    finally:
        numba.set_num_threads(threads)
    return SetupRate(count, sum(s.n_pixels for s, _ in collected), best, best_setup)
