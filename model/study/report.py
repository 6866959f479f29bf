# SPDX-License-Identifier: Apache-2.0
"""Methods side by side on one scene: images, accuracy against (a), hardware cost, speed.

The methods (``METHOD_LABELS``): (a) exact float Blinn with per-pixel spherical interpolation of
N and H, the accuracy reference; (b) classic float Phong; (c)-(h) the bit-exact unit pipelines of
``model.pipeline``.  Every method shades the same rasterised spans (one ``rasterise`` per scene),
so the figures isolate the shading.  Accuracy is measured against (a) with ``model.metrics``;
hardware cost comes from the units' cycle counts (``pipeline.unit_counters``) and ROM sizes;
software speed is the best of ``repeats`` timed runs after one warm-up run (numba compiles on
the first call), as shaded pixels per second.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from model.render import pipeline, raster, reference, scene, scenefile, shade
from model.study import images, metrics
from model.units import brdf, specular

METHOD_LABELS: dict[str, str] = {
    "exact": "(a) exact Blinn, spherical interpolation (float)",
    "phong": "(b) classic Phong (float)",
    "hybrid": "(c) units: patent k-set, a = sqrt(n/k)",
    "inflection": "(d) units: inflection-matched a",
    "prototype": "(e) units: prototype cos^2",
    "gouraud": "(f) units: Gouraud only",
    "adaptive": "(g) units: structure-adaptive",
    "diffuse": "(h) units: diffuse through the specular unit (n = 1)",
    "cosine_quadratic": "(i) units: cosine-quadratic BRDF unit, no coefficient table",
    "quadratic": "(j) units: quadratic BRDF unit, a per n",
    "cubic": "(k) units: cubic BRDF unit, r p0 b1 b2 per n",
    "log2": "(l) units: log2 BRDF unit, n x -log2 cos, a log2 table",
    "piecewise": "(m) units: piecewise BRDF unit, the cubic and the divided bloom, six words per n",
}
FLOAT_SHADERS = {"exact": reference.exact_blinn, "phong": reference.phong}
DEFAULT_SCENE = "teapot"
DEFAULT_SIZE = 256


class SetupError(Exception):
    """A command cannot start (an output folder it cannot write, an unreachable scheduler, a
    sweep already running on the same cache): found before any work; the command line prints
    the message as one line and exits with ``status`` (2: a bad argument, 1: otherwise)."""

    def __init__(self, message: str, status: int = 1) -> None:
        super().__init__(message)
        self.status = status


def check_output_dir(arg: str, path: Path) -> Path:
    """Create ``path`` (a folder) and write a scratch file into it, before any work: or raise
    ``SetupError`` (status 2) naming the argument ``arg``, the path and why it cannot be used."""
    import tempfile

    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
        fd, scratch = tempfile.mkstemp(dir=path, prefix=".write-test-")
        os.close(fd)
        os.unlink(scratch)
    except OSError as exc:
        why = exc.strerror or exc.__class__.__name__
        if path.exists() and not path.is_dir():
            why = "it is a file, not a folder"
        raise SetupError(
            f"argument {arg}: '{path}' is not allowed: {why}: must be a folder this user can "
            "create and write in",
            status=2,
        ) from None
    return path


def shader_for(method: str, cfg: pipeline.PipelineConfig | None = None) -> shade.Shader:
    if method in FLOAT_SHADERS:
        return FLOAT_SHADERS[method]
    if cfg is None:
        cfg = method_config(method)
    return pipeline.unit_shader(cfg)


def method_config(method: str) -> pipeline.PipelineConfig:
    """The ``PipelineConfig`` of a units method (``pipeline.METHODS`` or ``BRDF_METHODS``)."""
    found = {**pipeline.METHODS, **pipeline.BRDF_METHODS}.get(method)
    if found is None:
        raise ValueError(
            f"method = {method!r} is out of range: legal methods are {', '.join(METHOD_LABELS)}"
        )
    return found


def table_bits(method: str, cfg: pipeline.PipelineConfig | None = None) -> int:
    """ROM bits the method's units hold (0 for the float methods)."""
    if method in FLOAT_SHADERS:
        return 0
    cfg = cfg or method_config(method)
    bits = cfg.divider.rom_bits
    if cfg.brdf is not None:
        bits += brdf.table_bits(cfg.brdf)["total"]
    elif cfg.uses_specular_unit:
        bits += cfg.specular.rom_bits
    return bits


@dataclass(frozen=True)
class MethodResult:
    name: str
    label: str
    frame: shade.Frame
    comparison: metrics.Comparison
    seconds: float  # best shading time of the timed runs
    table_bits: int

    @property
    def pixels_per_second(self) -> float:
        return self.frame.stats.pixels_shaded / max(self.seconds, 1e-12)

    @property
    def counters(self) -> dict:
        return dict(self.frame.stats.counters)


@dataclass(frozen=True)
class SceneRun:
    scene_name: str
    raster: raster.Raster
    reference: shade.Frame
    highlight: np.ndarray
    results: dict[str, MethodResult]


def run_methods(
    scene_name: str | scene.Scene = DEFAULT_SCENE,
    size: int = DEFAULT_SIZE,
    methods: list[str] | None = None,
    repeats: int = 1,
    progress: bool = False,
    configs: dict[str, pipeline.PipelineConfig] | None = None,
) -> SceneRun:
    """Rasterise once, shade with every method, compare each with (a).

    ``scene_name`` is a built-in scene's name (made ``size`` x ``size``) or a ``Scene`` (a scene
    file's or a mesh file's, ``scenefile.SceneSource.scene``), shaded at its own camera's size."""
    methods = list(methods or METHOD_LABELS)
    configs = configs or {}
    if isinstance(scene_name, scene.Scene):
        the_scene = scene_name
    else:
        the_scene = scenefile.builtin_scene(scene_name, size, size)
    scene_name, size = the_scene.name, the_scene.camera.width
    frame_raster = raster.rasterise(the_scene)
    ref = shade.shade(frame_raster, reference.exact_blinn)
    highlight = metrics.highlight_mask(ref.specular)
    ref_levels = ref.rgb.astype(np.float64)  # converted once: the metrics work in float64
    results = {}
    for name in tqdm(methods, desc=f"{scene_name} {size}x{size}", disable=not progress):
        shader = shader_for(name, configs.get(name))
        shade.shade(frame_raster, shader)  # warm-up: numba compiles on the first call
        best, frame = math.inf, None
        for _ in range(max(1, repeats)):
            frame = shade.shade(frame_raster, shader)
            best = min(best, frame.stats.shade_seconds)
        results[name] = MethodResult(
            name=name,
            label=METHOD_LABELS.get(name, name),
            frame=frame,
            comparison=metrics.compare(
                frame.rgb.astype(np.float64), ref_levels, highlight=highlight
            ),
            seconds=best,
            table_bits=table_bits(name, configs.get(name)),
        )
    return SceneRun(scene_name, frame_raster, ref, highlight, results)


def format_table(run: SceneRun) -> str:
    """The comparison table (markdown): accuracy against (a), hardware cost, software speed."""
    lines = [
        "| method | NMSE | PSNR dB | max err | px > 1 level | highlight max err "
        "| divider cycles | Gouraud cycles | specular cycles | specular px | diffuse cycles "
        "| table bits | Mpx/s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in run.results.values():
        c, k = r.comparison, r.counters
        lines.append(
            f"| {r.label} | {c.nmse:.6f}{' ✓' if c.visually_identical else ''} "
            f"| {c.psnr:.1f} | {c.max_abs_error:.0f} | {100 * c.share_off_by_more_than_1:.2f} % "
            f"| {c.highlight_max_abs_error:.0f} "
            f"| {k.get('divider_cycles', '-')} | {k.get('gouraud_cycles', '-')} "
            f"| {k.get('specular_cycles', '-')} | {k.get('specular_pixels', '-')} "
            f"| {k.get('diffuse_cycles', '-')} | {r.table_bits} | {r.pixels_per_second / 1e6:.2f} |"
        )
    lines.append("")
    lines.append(
        f"NMSE against (a); ✓ = NMSE <= {metrics.NMSE_VISUALLY_IDENTICAL} (the thesis's "
        f"'visually identical'); highlight = {int(run.highlight.sum())} pixels where (a)'s "
        "specular term exceeds 8 levels; cycles are start-to-start clocks summed over the "
        "frame's jobs (Gouraud: one unit per colour channel; diffuse: the jobs of the diffuse "
        "term on the specular unit at n = 1, one per span and channel)."
    )
    return "\n".join(lines)


def requirements(run: SceneRun) -> str:
    """What the scene needs of the hardware: ROM-9 entries, tables, widths, adaptive split."""
    stats = run.reference.stats
    n_values = stats.n_values
    ks = sorted({specular.decode_k(n) for n in n_values})
    longest = stats.longest_span
    intervals = max(longest - 1, 1)
    lines = [
        f"n values used: {', '.join(map(str, n_values))} -> {len(n_values)} of the 1000 ROM-9 "
        f"entries, cos^k tables for k = {', '.join(map(str, ks))} "
        f"({len(ks)} of {specular.DEFAULT.num_tables})",
        f"longest span: {longest} pixels ({longest - 1} intervals) -> interval counter and "
        f"divider k need {intervals.bit_length()} bits (default 11: lines up to 2047)",
    ]
    adaptive = run.results.get("adaptive")
    if adaptive is not None:
        k = adaptive.counters
        spec_tri = int(k.get("specular_triangles", 0))
        total = int(k.get("triangles", 0))
        lines.append(
            f"adaptive: {spec_tri} of {total} shaded triangles through the specular unit, "
            f"{total - spec_tri} Gouraud only; {k.get('specular_pixels', 0)} of "
            f"{adaptive.frame.stats.pixels_shaded} pixels through the specular unit"
        )
    return "\n".join(lines)


def sheet_args(run: SceneRun, log_error: bool = False) -> dict:
    """What the demo sheet shows (``images.sheet_data``'s arguments): (a) as the reference in
    the left column, every other method with its error map against it."""
    size = run.reference.rgb.shape[0]
    ref_name = next(iter(run.results))
    return {
        "panels": [(r.label, r.frame.rgb) for n, r in run.results.items() if n != ref_name],
        "title": f"{run.scene_name}, {size} x {size}: every method, and its error against (a)",
        "error_reference": run.reference.rgb,
        "reference_label": run.results[ref_name].label,
        "log_error": bool(log_error),
    }


def sheet_record(run: SceneRun, log_error: bool = False, data: dict | None = None) -> dict:
    """What the demo sheet was made from: scene, size, scale and the digest of the data it plots
    (``images.data_digest`` of ``images.sheet_data``; ``data`` if already computed)."""
    if data is None:
        data = images.sheet_data(**sheet_args(run, log_error))
    return {
        "scene": run.scene_name,
        "size": int(run.reference.rgb.shape[0]),
        "log_error": bool(log_error),
        "data_sha256": images.data_digest(data),
    }


def write_images(run: SceneRun, out_dir: Path, log_error: bool = False) -> list[Path]:
    """PNG per method, error heat-maps against (a) (each on its own scale; symmetric-log with
    ``log_error``) and one side-by-side sheet (the last path), with ``<scene>_sheet.json``
    beside it: what the sheet was made from (``sheet_record``; ``make pictures`` records it)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    written = [
        images.save_png(out_dir / f"{run.scene_name}_{name}.png", r.frame.rgb)
        for name, r in run.results.items()
    ]
    # The sheet's data holds every error map against (a): the heat-maps reuse them.
    data = images.sheet_data(**sheet_args(run, log_error))
    ref_name = next(iter(run.results))
    others = [n for n in run.results if n != ref_name]
    maps = {n: panel["error"] for n, panel in zip(others, data["panels"], strict=True)}
    shown = [n for n in run.results if n != "exact"]
    written += images.save_error_heatmaps(
        [
            (
                out_dir / f"{run.scene_name}_{n}_error.png",
                run.results[n].frame.rgb,
                run.results[n].label,
            )
            for n in shown
        ],
        run.reference.rgb,
        log=log_error,
        reference_label="(a)",
        errors=[maps[n] for n in shown] if all(n in maps for n in shown) else None,
    )
    sheet = out_dir / f"{run.scene_name}_sheet.png"
    written.append(images.draw_sheet(sheet, data, columns=3))
    record = {"picture": sheet.name, **sheet_record(run, log_error, data)}
    sheet.with_suffix(".json").write_text(json.dumps(record, indent=2) + "\n")
    return written


# ================================================================= the pictures the docs show
PICTURES_JSON = Path("docs/pictures.json")
DEMO_SHEET = "docs/demo_sheet.png"
DEMO_COMMAND = "python -m model demo"
TRADE_FIGURE = "docs/trade_pareto.png"
TRADE_COMMAND = "python -m model trade --figure docs/"


def trade_results_record(csv_path: Path) -> dict:
    """What a sweep's ``results.csv`` holds, without its timings (they differ on every run) and
    without the synthesised columns (``trade.HW_FIELDS``: they come from the synthesis tools, whose
    own record is docs/synth.json; leaving them out lets a check re-sweep with ``part=None``):
    the scenes, sizes and number of rows, and a digest of every other column (rows sorted,
    floats to 6 significant digits)."""
    import csv

    from model.study.trade.hardware import HW_FIELDS

    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    columns = sorted(
        c for c in (rows[0] if rows else {}) if "second" not in c and c not in HW_FIELDS
    )

    def value(text: str) -> float | str:
        try:
            return float(text)
        except ValueError:
            return text

    table = sorted(tuple(r[c] for c in columns) for r in rows)
    return {
        "made_from": str(csv_path),
        "scenes": sorted({r.get("scene", "") for r in rows}),
        "sizes": sorted({int(r["size"]) for r in rows if r.get("size", "").isdigit()}),
        "rows": len(rows),
        "data_sha256": images.data_digest(
            {"columns": columns, "rows": [[value(v) for v in row] for row in table]}
        ),
    }


def record_pictures(
    demo_out: Path = Path("out"),
    trade_out: Path = Path("out/trade"),
    record_path: Path = PICTURES_JSON,
) -> dict:
    """``make pictures``' last step, after ``python -m model demo`` and ``python -m model trade
    --figure docs/``: copy the demo's sheet to docs/demo_sheet.png and write docs/pictures.json,
    per picture the command that makes it and what it was made from (a digest of the numbers it
    plots; for the trade figure, of the sweep's results).  ``tests/test_pictures.py`` checks it."""
    import shutil

    sidecar = Path(demo_out) / f"{DEFAULT_SCENE}_sheet.json"
    if not sidecar.is_file():
        raise SetupError(f"'{sidecar}' is missing: run `{DEMO_COMMAND}` first")
    sheet = json.loads(sidecar.read_text())
    wanted = {"scene": DEFAULT_SCENE, "size": DEFAULT_SIZE, "log_error": False}
    made = {k: sheet.get(k) for k in wanted}
    if made != wanted:
        raise SetupError(
            f"'{sidecar}' is of {made}, not the README's picture {wanted}: run `{DEMO_COMMAND}`"
        )
    results = Path(trade_out) / "results.csv"
    for needed in (results, Path(TRADE_FIGURE)):
        if not needed.is_file():
            raise SetupError(f"'{needed}' is missing: run `{TRADE_COMMAND}` first")
    Path(DEMO_SHEET).parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(sidecar.with_name(sheet["picture"]), DEMO_SHEET)
    record = {
        "made_by": "make pictures",
        "about": (
            "Every picture README.md and docs/ show: the command that makes it and a SHA-256 of "
            "the numbers it plots (model.study.images.data_digest), not of the PNG bytes, which "
            "change with the Pillow, matplotlib and zlib versions. tests/test_pictures.py checks "
            "them."
        ),
        "pictures": {
            DEMO_SHEET: {
                "command": DEMO_COMMAND,
                "copied_from": str(sidecar.with_name(sheet["picture"])),
                **{k: sheet[k] for k in ("scene", "size", "log_error", "data_sha256")},
            },
            TRADE_FIGURE: {"command": TRADE_COMMAND, **trade_results_record(results)},
        },
    }
    record_path = Path(record_path)
    record_path.write_text(json.dumps(record, indent=2) + "\n")
    return record


if __name__ == "__main__":  # `python -m model.study.report pictures` (make pictures)
    import sys

    if sys.argv[1:] != ["pictures"]:
        sys.exit("usage: python -m model.study.report pictures")
    try:
        done = record_pictures()
    except SetupError as exc:
        sys.exit(f"make pictures: error: {exc}")
    for picture, entry in done["pictures"].items():
        print(f"{picture}: {entry['command']} (data {entry['data_sha256'][:12]})")
    print(f"wrote {PICTURES_JSON}")
