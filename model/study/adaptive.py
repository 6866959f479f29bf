# SPDX-License-Identifier: Apache-2.0
"""What structure-adaptive shading (method (g)) gains over the hybrid pipeline (c), against n.

The thesis reports that sending only the triangles the highlight test flags through the specular
unit makes shading 1.5-2x faster, less for n < 30 (the highlights are large, so more triangles
are flagged).  ``adaptive_gain`` measures both sides of that claim on one scene for a sweep of
the shininess n (every object's material set to n): the gain in hardware frame clocks
(``trade.frame_clocks``: the units in parallel) and the gain in software time (best of
``repeats`` shadings of the same raster, (c) and (g) taking turns; in wall time and in the
thread's CPU time, which other processes on a busy machine do not change), beside the share of
triangles flagged and the accuracy of each.  ``format_gain`` prints the table and what it says
about the claim. May import ``model.render``, ``model.units`` and ``model.study``.
"""

from __future__ import annotations

import dataclasses
import math
import time

from model.render import pipeline, raster, reference, scene, scenefile, shade
from model.study import metrics
from model.study.trade import frame_clocks

DEFAULT_NS = (2, 5, 10, 20, 30, 50, 100, 200, 500, 1000)
HYBRID = pipeline.unit_shader(pipeline.METHODS["hybrid"])
ADAPTIVE = pipeline.unit_shader(pipeline.METHODS["adaptive"])
CLAIM = (1.5, 2.0)  # the thesis's gain of structure-adaptive shading
SMALL_N = 30  # "less for n < 30"


def with_shininess(the_scene: scene.Scene, n: int) -> scene.Scene:
    """``the_scene`` with every object's material exponent set to ``n``."""
    objects = tuple(
        dataclasses.replace(o, material=dataclasses.replace(o.material, n=n))
        for o in the_scene.objects
    )
    return dataclasses.replace(the_scene, objects=objects)


def _timed(frame_raster: raster.Raster, shader: shade.Shader) -> tuple[shade.Frame, float]:
    """The frame and the calling thread's CPU seconds for it."""
    began = time.thread_time()
    frame = shade.shade(frame_raster, shader)
    return frame, time.thread_time() - began


def _best(
    frame_raster: raster.Raster, shaders: list, repeats: int
) -> list[tuple[shade.Frame, float]]:
    """Each shader's fastest frame of ``repeats`` and its least CPU seconds (after a
    warm-up: numba compiles or loads its cache on the first call), the shaders taking turns so
    that the machine's load falls on each alike."""
    for shader in shaders:
        shade.shade(frame_raster, shader)
    runs = [[_timed(frame_raster, s) for s in shaders] for _ in range(max(1, repeats))]
    return [
        (
            min((r[i][0] for r in runs), key=lambda f: f.stats.shade_seconds),
            min(r[i][1] for r in runs),
        )
        for i in range(len(shaders))
    ]


def adaptive_gain(
    scene_name: str = "teapot", size: int = 256, ns=DEFAULT_NS, repeats: int = 3
) -> list[dict]:
    """One row per n: frame clocks and software seconds of (c) and (g), their ratios, the
    triangles (g) sends through the specular unit, and each method's NMSE against (a)."""
    base = scenefile.builtin_scene(scene_name, size, size)
    rows = []
    for n in ns:
        frame_raster = raster.rasterise(with_shininess(base, int(n)))
        ref = shade.shade(frame_raster, reference.exact_blinn).rgb
        (c, cpu_c), (g, cpu_g) = _best(frame_raster, [HYBRID, ADAPTIVE], repeats)
        kc, kg = c.stats.counters, g.stats.counters
        rows.append(
            {
                "scene": scene_name,
                "size": size,
                "n": int(n),
                "clocks_c": frame_clocks(kc),
                "clocks_g": frame_clocks(kg),
                "clock_gain": frame_clocks(kc) / max(frame_clocks(kg), 1),
                "seconds_c": c.stats.shade_seconds,
                "seconds_g": g.stats.shade_seconds,
                "software_gain": c.stats.shade_seconds / max(g.stats.shade_seconds, 1e-12),
                "cpu_c": cpu_c,
                "cpu_g": cpu_g,
                "cpu_gain": cpu_c / max(cpu_g, 1e-12),
                "flagged": kg.get("specular_triangles", 0) / max(kg.get("triangles", 1), 1),
                "nmse_c": metrics.nmse(c.rgb, ref),
                "nmse_g": metrics.nmse(g.rgb, ref),
            }
        )
    return rows


def verdict(rows: list[dict], key: str) -> str:
    """What the rows say about the thesis's 1.5-2x (``key``: "clock_gain" or
    "software_gain"), for n >= 30 and for n < 30."""

    def span(values: list[float]) -> str:
        return f"{min(values):.2f}x..{max(values):.2f}x" if values else "-"

    big = [r[key] for r in rows if r["n"] >= SMALL_N]
    small = [r[key] for r in rows if r["n"] < SMALL_N]
    held = bool(big) and min(big) >= CLAIM[0]
    less = bool(small) and bool(big) and max(small) <= min(big)
    return (
        f"n >= {SMALL_N}: {span(big)} ({'at least' if held else 'below'} the thesis's "
        f"{CLAIM[0]}x, which reports {CLAIM[0]}-{CLAIM[1]}x); n < {SMALL_N}: {span(small)} "
        f"({'less, as the thesis says' if less else 'not less than for larger n'})"
    )


def format_gain(rows: list[dict]) -> str:
    """The table (markdown) and the verdicts on the thesis's claim."""
    lines = [
        "| scene | n | frame clocks (c) | frame clocks (g) | gain in clocks | software (c) ms "
        "| software (g) ms | gain in software | gain in CPU time | triangles flagged | NMSE (c) "
        "| NMSE (g) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['scene']} {r['size']} | {r['n']} | {r['clocks_c']:,} | {r['clocks_g']:,} "
            f"| {r['clock_gain']:.2f}x | {1e3 * r['seconds_c']:.2f} | {1e3 * r['seconds_g']:.2f} "
            f"| {r['software_gain']:.2f}x | {r['cpu_gain']:.2f}x | {100 * r['flagged']:.0f} % "
            f"| {r['nmse_c']:.6f} "
            f"| {r['nmse_g']:.6f} |"
        )
    for scene_name in dict.fromkeys(r["scene"] for r in rows):
        mine = [r for r in rows if r["scene"] == scene_name]
        lines += [
            "",
            f"{scene_name}: frame clocks {verdict(mine, 'clock_gain')}",
            f"{scene_name}: software {verdict(mine, 'software_gain')}",
            f"{scene_name}: CPU time {verdict(mine, 'cpu_gain')}",
        ]
    finite = [r for r in rows if math.isfinite(r["software_gain"])]
    if len(finite) != len(rows):  # pragma: no cover - a zero shading time
        lines.append("(some software times were too short to compare)")
    return "\n".join(lines)
