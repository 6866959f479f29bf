# SPDX-License-Identifier: Apache-2.0
"""``python -m model bench``: the bit-exact pipeline's speed against float shaders, in one run.

Every scene is rasterised once per size; each shader then shades it (a warm-up, then the best of
``repeats`` timed runs of ``shade.shade``, the rows taking turns: the shading only, frame fill
and scatter included, the rasterisation not).  Rows: (a) exact float Blinn and (b) Phong (numba
kernels), ``numpy_blinn`` (a plain vectorised numpy float Blinn-Phong: what a user would write
instead), the hybrid (c) and the adaptive (g) pipelines on one core (the fused kernel), the same
over numba's threads, and (c) through the units' batched calls (``unit_shader(cfg, "units")``,
the reference path the fused one is tested against), and the ceiling row (``ceiling``: the
set-up's transcendental calls alone, the floor under any bit-exact (c)).  The ratios are what
to compare: absolute speeds vary with the machine and its load.  ``format_adaptive`` prints (g)
against (c) per scene and size.  Owns ``numpy_blinn``, ``measure``, ``format_table``,
``format_adaptive``, ``targets`` and ``main``.  May import numpy, ``model.render`` and
``model.study.ceiling``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from model.render import pipeline, raster, reference, scenefile, shade
from model.render.highlight import object_highlight_flags as fast_flags
from model.render.scene import Scene
from model.render.shade import ShadeContext, ShadeResult
from model.render.spans import Spans
from model.render.vectors import LIGHT_DIRECTIONAL
from model.study import ceiling

SIZES = (64, 512, 1024)
THREAD_REST = 0.05  # seconds after the threaded rows (``measure``)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def numpy_blinn(spans: Spans, ctx: ShadeContext) -> ShadeResult:
    """Float Blinn-Phong in plain vectorised numpy, per pixel: the normal and the position
    interpolated linearly and normalised, L, V and H per pixel, ambient + diffuse + specular,
    rounded to 8 bits.  What a user would write instead of the units (method (b)'s maths)."""
    idx = np.repeat(np.arange(len(spans)), spans.lengths)
    t = spans.pixel_t()[:, None]
    n0, p0 = spans.nlin_start[idx], spans.p_start[idx]
    normal = _unit(n0 + t * (spans.nlin_end[idx] - n0))
    pos = p0 + t * (spans.p_end[idx] - p0)
    lp, m = ctx.lighting, ctx.material
    light = _unit(lp.lvec) if lp.light_kind == LIGHT_DIRECTIONAL else _unit(lp.lvec - pos)
    view = _unit(lp.vvec - pos) if lp.viewer_local else lp.vvec
    half = _unit(light + view)
    ndl = np.maximum(0.0, (normal * light).sum(axis=1))
    ndh = np.maximum(0.0, (normal * half).sum(axis=1))
    spec = 255.0 * m.k_s * lp.intensity * ndh**m.n
    colour = 255.0 * np.asarray(m.colour, dtype=np.float64)
    rgb = colour * (m.ambient + m.k_d * lp.intensity * ndl)[:, None] + spec[:, None]
    return ShadeResult(reference.quantise(rgb), spec)


# (row name, label, shader)
ROWS = (
    ("exact", "(a) exact Blinn", reference.exact_blinn),
    ("phong", "(b) Phong", reference.phong),
    ("numpy", "numpy float Blinn", numpy_blinn),
    ("hybrid", "(c) hybrid", pipeline.unit_shader(pipeline.METHODS["hybrid"])),
    (
        "hybrid_mt",
        "(c) hybrid, threads",
        pipeline.unit_shader(pipeline.METHODS["hybrid"], "threads"),
    ),
    ("adaptive", "(g) adaptive", pipeline.unit_shader(pipeline.METHODS["adaptive"])),
    (
        "adaptive_mt",
        "(g) adaptive, threads",
        pipeline.unit_shader(pipeline.METHODS["adaptive"], "threads"),
    ),
    (
        "hybrid_units",
        "(c) via batched unit calls",
        pipeline.unit_shader(pipeline.METHODS["hybrid"], "units"),
    ),
    ("floor", "(c) ceiling: its set-up's floor", ceiling.setup_floor),
)


@dataclass(frozen=True)
class Measurement:
    """One scene at one size: shaded pixels and the best seconds of every row."""

    scene: str
    size: int
    pixels: int
    seconds: dict[str, float]
    spans: int = 0
    cpu: dict[str, float] | None = None  # best CPU seconds of the calling thread, per row

    def mpx(self, row: str) -> float:
        """Shaded megapixels per second of ``row``."""
        s = self.seconds[row]
        return self.pixels / s / 1e6 if s > 0 else math.inf

    def ratio(self, row: str, to: str) -> float:
        return self.seconds[to] / self.seconds[row] if self.seconds[row] > 0 else math.inf

    def cpu_ratio(self, row: str, to: str) -> float:
        """``ratio`` in the calling thread's CPU time (not slowed by other processes; only for
        rows on one thread)."""
        cpu = self.cpu or {}
        if row not in cpu or to not in cpu:
            return math.nan
        return cpu[to] / cpu[row] if cpu[row] > 0 else math.inf


def measure(the_scene: Scene, repeats: int, rows=ROWS) -> Measurement:
    """Rasterise once, then every row's best shading time of ``repeats`` (after a warm-up).
    The rows take turns within each repeat, so that a change in the machine's load falls on
    every row alike (the ratios are what to compare); the rows on numba's threads (``_mt``)
    go last, then a pause of ``THREAD_REST`` s: their idle OpenMP workers spin for a while
    after a parallel region and would slow down the row timed next (measured: (g) after a
    threaded row took twice its time on 2 cores)."""
    frame_raster = raster.rasterise(the_scene)
    seconds, pixels, spans = dict.fromkeys((name for name, _, _ in rows), math.inf), 0, 0
    cpu = dict(seconds)
    order = sorted(rows, key=lambda row: row[0].endswith("_mt"))  # stable: threads last
    for _, _, shader in order:
        shade.shade(frame_raster, shader)  # warm-up: numba compiles or loads its cache
    time.sleep(THREAD_REST)
    for _ in range(max(1, repeats)):
        for name, _, shader in order:
            began = time.thread_time()
            frame = shade.shade(frame_raster, shader)
            cpu[name] = min(cpu[name], time.thread_time() - began)
            seconds[name] = min(seconds[name], frame.stats.shade_seconds)
            pixels, spans = frame.stats.pixels_shaded, frame.stats.spans_shaded
        time.sleep(THREAD_REST)
    return Measurement(the_scene.name, the_scene.camera.width, pixels, seconds, spans, cpu)


def format_table(runs: list[Measurement], rows=ROWS) -> str:
    """The markdown table: per scene and size, each row's Mpx/s and its ratios."""
    lines = [
        "| scene | size | shaded px | px per span | method | Mpx/s | vs (a) exact "
        "| vs numpy Blinn | vs (c) hybrid |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for m in runs:
        per_span = f"{m.pixels / m.spans:.1f}" if m.spans else "-"
        for name, label, _ in rows:
            lines.append(
                f"| {m.scene} | {m.size} | {m.pixels:,} | {per_span} | {label} | {m.mpx(name):.2f} "
                f"| {m.ratio(name, 'exact'):.2f}x | {m.ratio(name, 'numpy'):.2f}x "
                f"| {m.ratio(name, 'hybrid'):.2f}x |"
            )
    return "\n".join(lines)


def format_adaptive(runs: list[Measurement]) -> str:
    """(g) against (c) in software, one row per scene, one column per size: the speed of (g)
    as a multiple of (c)'s (> 1: (g) is faster) in wall time (the table's) and in the thread's
    CPU time (``shade.shade`` on one thread: what a busy machine does not change), from the
    same runs as the table."""
    sizes = sorted({m.size for m in runs})
    lines = [
        "| scene | " + " | ".join(f"(g) / (c) at {n}, wall | CPU" for n in sizes) + " |",
        "|---|" + "---|---|" * len(sizes),
    ]
    for scene in dict.fromkeys(m.scene for m in runs):
        by_size = {m.size: m for m in runs if m.scene == scene}
        cells = [
            f"{by_size[n].ratio('adaptive', 'hybrid'):.2f}x | "
            f"{by_size[n].cpu_ratio('adaptive', 'hybrid'):.2f}x"
            if n in by_size
            else "- | -"
            for n in sizes
        ]
        lines.append(f"| {scene} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def targets(runs: list[Measurement]) -> list[str]:
    """The issue's targets, each met or not met with its worst measured ratio (only the sizes
    measured count; a target with no measured size says so)."""
    checks = []
    for row, label in (("hybrid", "(c) hybrid"), ("adaptive", "(g) adaptive")):
        checks.append((f"{label} >= 10x (a) at 512 and 1024", row, "exact", 10.0, (512, 1024)))
        checks.append((f"{label} >= 3x (a) at 64", row, "exact", 3.0, (64,)))
    checks.append(("(c) hybrid >= 5x numpy float Blinn at 1024", "hybrid", "numpy", 5.0, (1024,)))
    checks.append(("(g) adaptive faster than (c) at 512 and 1024", "adaptive", "hybrid", 1.0,
                   (512, 1024)))  # fmt: skip
    out = []
    for text, row, to, goal, sizes in checks:
        got = [m.ratio(row, to) for m in runs if m.size in sizes]
        if not got:
            out.append(f"target: {text}: not measured (no run at {sizes})")
            continue
        worst = min(got)
        out.append(f"target: {text}: worst {worst:.2f}x ({'met' if worst >= goal else 'not met'})")
    return out


def unit_calls(pixels: int = 1 << 20, line: int = 16, repeats: int = 3) -> dict[str, float]:
    """Mpx/s of the public batched unit calls (``gouraud.shade_lines``, three channels as the
    pipeline calls it, and ``specular.shade_lines``) on ``pixels`` pixels in lines of ``line``
    pixels with random legal operands, the best of ``repeats`` calls after a warm-up."""
    from model.units import gouraud, specular

    rng = np.random.default_rng(2026)
    lines = max(1, pixels // line)
    g, s = gouraud.DEFAULT, specular.DEFAULT
    i0 = rng.integers(0, 1 << g.i_width, (lines, 3))
    di = rng.integers(-(1 << g.i_frac), 1 << g.i_frac, (lines, 3))
    glen = np.full(lines, line)
    c = rng.integers(0, 1 << s.c_width, lines)
    dz = rng.integers(-(1 << 20), 1 << 20, lines)
    z0 = rng.integers(-(1 << (s.z_frac_bits + 1)), 1 << (s.z_frac_bits + 1), lines)
    n = rng.integers(1, specular.N_MAX + 1, lines)
    slen = np.full(lines, line - 1)
    calls = {
        "gouraud.shade_lines (3 channels)": (
            lambda: gouraud.shade_lines(i0, di, glen),
            3 * lines * line,
        ),
        "specular.shade_lines": (lambda: specular.shade_lines(c, dz, z0, n, slen), lines * line),
    }
    found = {}
    for name, (call, done) in calls.items():
        call()  # numba compiles on the first call
        best = math.inf
        for _ in range(max(1, repeats)):
            t = time.perf_counter()
            call()
            best = min(best, time.perf_counter() - t)
        found[name] = done / best / 1e6
    return found


def highlight_test_times(
    scenes: list[Scene], repeats: int = 5
) -> list[tuple[str, int, float, float]]:
    """(scene, triangles, numpy seconds, kernel seconds): the host's highlight test over every
    triangle of each scene's objects, ``reference.object_highlight_flags`` (numpy) against
    ``highlight.object_highlight_flags`` (the kernel, the same bools), best of ``repeats``."""
    found = []
    for sc in scenes:
        objects = range(len(sc.objects))
        best = {}
        for name, test in (("numpy", reference.object_highlight_flags), ("kernel", fast_flags)):
            for o in objects:
                test(sc, o)  # numba compiles or loads its cache on the first call
            best[name] = math.inf
            for _ in range(max(1, repeats)):
                t = time.perf_counter()
                for o in objects:
                    test(sc, o)
                best[name] = min(best[name], time.perf_counter() - t)
        count = sum(len(o.mesh.triangles) for o in sc.objects)
        found.append((sc.name, count, best["numpy"], best["kernel"]))
    return found


def main(
    sources: list[scenefile.SceneSource],
    sizes: list[int],
    repeats: int,
    studies: bool = False,
    out_dir: Path = Path("out"),
) -> int:
    """Measure every source at every size (a scene file or a mesh at its own size: the first
    of ``sizes``) and print the table and the targets; with ``studies`` also the adaptive
    method's gain against n (``model.study.adaptive``) and the scaling with image size and
    triangle count (``model.study.scaling``, plotted to ``out_dir``/bench_scaling.png)."""
    runs = []
    for source in sources:
        for size in sizes:
            runs.append(measure(source.scene(size, size), repeats))
    head = f"{', '.join(s.label for s in sources)} {', '.join(f'{n} x {n}' for n in sizes)}"
    print(f"== bench: {head}, best of {repeats} (shading only) ==")
    print("(the frame fill, the shader and the scatter into the frame; not the rasterisation)")
    print(format_table(runs))
    print("\n== (g) adaptive against (c) hybrid in software (the same runs) ==")
    print(format_adaptive(runs))
    print()
    print("\n".join(targets(runs)))
    print("\n".join(ceiling.ceiling_lines(runs)))
    print("\n== the host's highlight test of (g), every triangle, best of 5 ==")
    print("| scene | triangles | numpy ms | kernel ms | kernel speed-up |\n|---|---|---|---|---|")
    scenes = [source.scene(sizes[0], sizes[0]) for source in sources]
    for name, count, t_np, t_k in highlight_test_times(scenes):
        print(f"| {name} | {count:,} | {1e3 * t_np:.2f} | {1e3 * t_k:.3f} | {t_np / t_k:.0f}x |")
    print("\n== the public batched unit calls, 1M pixels in lines of 16 (target: 250 Mpx/s) ==")
    for name, speed in unit_calls(repeats=repeats).items():
        print(f"{name}: {speed:.1f} Mpx/s ({'met' if speed >= 250 else 'not met'})")
    if studies:
        from model.study import adaptive, scaling

        print("\n== (g) structure-adaptive against (c), a sweep of n (the thesis: 1.5-2x) ==")
        rows = [r for name in ("sphere", "teapot") for r in adaptive.adaptive_gain(name, 256)]
        print(adaptive.format_gain(rows))
        print("\n== scaling: Mpx/s against image size and triangle count ==")
        found = scaling.scaling(repeats=repeats)
        print(scaling.format_scaling(found))
        print(f"plot: {scaling.plot_scaling(found, Path(out_dir) / 'bench_scaling.png')}")
    print("the RTL co-simulation's speed: python -m sim bench (make bench runs both)")
    return 0
