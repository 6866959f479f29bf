"""The speed/accuracy trade study (``make trade``): every knob a config, swept over the scenes.

A **trade point** (``TradePoint``) is a scene, a resolution and one value per knob; every knob is
a field of one unit's configuration (``TradePoint.to_pipeline_config``), so the sweep runs the
same bit-exact pipeline as ``make demo`` with other configurations, never special code:

| knob | config field | default |
|---|---|---|
| ``rom_addr_bits`` | ``SpecularConfig.rom_addr_bits`` (ROM-12 address bits per table) | 12 |
| ``rom_data_bits`` | ``SpecularConfig.rom_data_bits`` (ROM-12 word bits) | 16 |
| ``z_frac_bits`` | ``SpecularConfig.z_frac_bits`` (angle fraction bits of dz, z0, acc) | 26 |
| ``k_set`` | ``SpecularConfig.k_ranges`` (``K_SETS``: the decoder's n -> k map) | patent |
| ``alpha`` | ``SpecularConfig.alpha`` (taylor a = sqrt(n/k), or inflection) | taylor |
| ``recip_bits`` | ``DividerConfig.recip_bits`` (N: reciprocal bits, shifts) | 20 |
| ``p`` | ``GouraudConfig.p`` (segment size: pixels per clock) | 8 |
| ``specular_mode`` | ``PipelineConfig.specular_mode`` (unit, adaptive, vertex) | unit |
| ``highlight_levels`` | ``PipelineConfig.highlight_levels`` (adaptive threshold) | 0.5 |

``SpecularConfig.a_int_bits`` follows from the k-set and alpha: the narrowest integer part that
holds the largest a (3 bits for k = 16 tables, 5 for the prototype's cos^2: a up to 22.4).

**Figures per point** (``evaluate``), against the exact float Blinn (a) of ``model.report``:
NMSE, PSNR, max error, highlight max error; the worst epicentre relative error of the unit's
ROM-12 path against cos^n over n = 1..1000 (``specular.fixed_point_accuracy``: where
cos^n >= 1/255; computed once per specular configuration, it does not depend on the scene); the
worst-case line drift of the divider + Gouraud increment over the longest line (levels; the
divider's figure that short scene spans cannot show); and cost:

* ``cycles``: unit cycles per frame, the sum of the busy-plus-restart clocks of every job of every
  unit (``pipeline.unit_counters``): the work, or the frame time of one unit of each kind in
  series.
* ``frame_clocks`` (critical-path estimate): the units work in parallel on a stream of spans,
  one divider and one Gouraud unit per colour channel (3 each) and one specular unit (white
  highlight), so a frame takes at least ``max(divider_cycles / 3, gouraud_cycles / 3,
  specular_cycles)`` clocks (ideal buffering between them).
* ``px_per_clock`` = shaded pixels / ``cycles``; ``px_per_clock_parallel`` = shaded pixels /
  ``frame_clocks``.
* ``table_bits``: one copy of every ROM (``report.table_bits``: divider reciprocals, and ROM 9 +
  ROM 12 unless the specular unit is left out).
* ``adders``, ``multipliers``: the datapath arithmetic of the units in the parallel picture:
  3 dividers x 1 accumulating adder, 3 Gouraud units x ``gouraud.adder_counts(P)["total"]``
  (increment network, segment lanes, rounding bias), 1 specular unit x (1 accumulator adder, 2
  multipliers: x a and x C), no specular unit in "vertex" mode.  Rounding increments, comparators,
  saturation and the final sum-and-saturate are not counted.  ``mult_bits``: the multipliers'
  partial-product bits (width x width), a proxy for their area.
* ``sw_pixels_per_second``: shaded pixels per second of the software model, best of ``repeats``
  timed runs after a warm-up (noisy: the workers share the machine).

**Engine** (``run_sweep``): Dask distributed futures, one per uncached point, collected with
``as_completed`` under a tqdm bar; a ``LocalCluster`` of worker processes by default, or an
existing cluster (``--scheduler ADDRESS``).  Every result is written at once, atomically, to
``<out>/cache/<key>.json``; a rerun evaluates only the keys not in the cache, so an interrupted
sweep resumes where it stopped.  A cache file that cannot be used (broken JSON, not an object, a
missing field, a figure out of ``RESULT_RANGES``) is evaluated again, and the run says so.  One
sweep at a time per cache: ``sweep_lock`` (``<out>/cache/sweep.lock``, ``fcntl.flock``) refuses a
second one at once with the pid of the first (it does not wait).  ``main`` checks the output
folders, the lock and the scheduler (``CONNECT_TIMEOUT``) before any work (``SetupError``).

**Outputs** (``write_outputs``): ``results.csv`` (one row per point), ``results.md`` (per config,
the mean/worst over the scenes, grouped by sweep, with the Pareto marks and what each knob buys),
``pareto_cycles.png`` and ``pareto_bits.png``.
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import functools
import hashlib
import itertools
import json
import math
import os
import tempfile
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from model.render import pipeline, raster, reference, scene
from model.study import metrics, report
from model.units import divider, gouraud, specular

CACHE_VERSION = 4
"""Part of every key: bump it when a figure's definition changes, so old cache files are unused."""
DEFAULT_SIZE = 128
DEFAULT_OUT = Path("out/trade")
CHANNELS = 3
NEAR = 0.05
"""Tolerance of "near the front": see ``eps_dominates``."""

K_SETS: dict[str, tuple[tuple[int, int, int], ...]] = {
    "patent": specular.PATENT_K_RANGES,  # k = 1, 2, 4, 16 (fig. 13)
    "k1-2-16": ((1, 1, 1), (2, 2, 2), (3, 1000, 16)),  # no cos^4 table: n = 3..6 use cos^16
    "k16": ((1, 1000, 16),),  # a single cos^16 table
    "cos2": specular.PROTOTYPE_K_RANGES,  # the prototype's single cos^2 table
}
"""The decoder's n -> k maps.  Without the cos^4 table, n = 3..6 are better served by cos^16
(worst float epicentre error 3.4 % at n = 3) than by cos^2 (4.4 % at n = 15)."""

KNOBS: tuple[str, ...] = (
    "rom_addr_bits",
    "rom_data_bits",
    "z_frac_bits",
    "k_set",
    "alpha",
    "recip_bits",
    "p",
    "specular_mode",
    "highlight_levels",
)


def _hash(payload: dict) -> str:
    text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class TradePoint:
    """One scene at one resolution through one configuration (the knobs: see the module doc)."""

    scene: str = "sphere"
    size: int = DEFAULT_SIZE
    rom_addr_bits: int = specular.DEFAULT.rom_addr_bits
    rom_data_bits: int = specular.DEFAULT.rom_data_bits
    z_frac_bits: int = specular.DEFAULT.z_frac_bits
    k_set: str = "patent"
    alpha: str = specular.DEFAULT.alpha
    recip_bits: int = divider.DEFAULT.recip_bits
    p: int = gouraud.DEFAULT.p
    specular_mode: str = "unit"
    highlight_levels: float = 0.5

    def __post_init__(self) -> None:
        scene.check_choice("scene", self.scene, scene.SCENE_NAMES)
        scene.check_choice("k_set", self.k_set, tuple(K_SETS))
        # Canonical types, so that equal points have equal keys (1 and 1.0, numpy ints).
        for name in ("size", "rom_addr_bits", "rom_data_bits", "z_frac_bits", "recip_bits", "p"):
            object.__setattr__(self, name, int(getattr(self, name)))
        object.__setattr__(self, "highlight_levels", float(self.highlight_levels))

    @property
    def knobs(self) -> dict[str, object]:
        return {k: getattr(self, k) for k in KNOBS}

    @property
    def key(self) -> str:
        """Stable cache key: hash of the canonical JSON of every field (and CACHE_VERSION)."""
        return _hash({"version": CACHE_VERSION, **dataclasses.asdict(self)})

    @property
    def config_key(self) -> str:
        """The same for the knobs only: equal for the scenes of one configuration."""
        return _hash({"version": CACHE_VERSION, **self.knobs})

    def with_knobs(self, **knobs) -> TradePoint:
        return dataclasses.replace(self, **knobs)

    def changed_knobs(self) -> dict[str, object]:
        """The knobs that differ from the default configuration."""
        base = TradePoint(scene=self.scene, size=self.size)
        return {k: v for k, v in self.knobs.items() if getattr(base, k) != v}

    @property
    def label(self) -> str:
        changed = self.changed_knobs()
        for name, knobs in NAMED.items():
            if changed == knobs:
                return name
        return ", ".join(f"{k}={v}" for k, v in changed.items()) if changed else "default"

    @property
    def group(self) -> str:
        """The sweep the configuration belongs to (its changed knob), for the plots."""
        changed = self.changed_knobs()
        if len(changed) == 1:
            return next(iter(changed))
        if set(changed) == {"specular_mode", "highlight_levels"}:
            return "highlight_levels"
        return "default" if not changed else "combined"

    def to_pipeline_config(self) -> pipeline.PipelineConfig:
        """The unit configurations this point's knobs select (every knob is one field)."""
        k_ranges = K_SETS[self.k_set]
        a_frac = specular.DEFAULT.a_frac_bits
        spec = specular.SpecularConfig(
            rom_addr_bits=self.rom_addr_bits,
            rom_data_bits=self.rom_data_bits,
            z_frac_bits=self.z_frac_bits,
            k_ranges=k_ranges,
            alpha=self.alpha,
            a_int_bits=a_int_bits_for(k_ranges, self.alpha, a_frac),
            a_frac_bits=a_frac,
        )
        return pipeline.PipelineConfig(
            divider=dataclasses.replace(divider.DEFAULT, recip_bits=self.recip_bits),
            gouraud=dataclasses.replace(gouraud.DEFAULT, p=self.p),
            specular=spec,
            specular_mode=self.specular_mode,
            highlight_levels=self.highlight_levels,
        )


@functools.cache
def a_int_bits_for(k_ranges: tuple, alpha: str, a_frac_bits: int) -> int:
    """The narrowest ROM-9 integer part holding the largest rounded a of the k-set (>= 1)."""
    a_max = max(
        specular.alpha_value(n, k, alpha) for lo, hi, k in k_ranges for n in range(lo, hi + 1)
    )
    word = math.floor(a_max * 2**a_frac_bits + 0.5)
    return max(1, word.bit_length() - a_frac_bits)


DEFAULT_POINT = TradePoint()


# ================================================================================ the grid
@dataclass(frozen=True)
class Sweep:
    """One knob swept around a base configuration (the default unless ``base`` overrides)."""

    knob: str
    values: tuple
    base: tuple[tuple[str, object], ...] = ()
    title: str = ""

    def configs(self) -> list[dict[str, object]]:
        return [{**dict(self.base), self.knob: v} for v in self.values]

    @property
    def base_knobs(self) -> dict[str, object]:
        return {**DEFAULT_POINT.knobs, **dict(self.base)}


SMALL_SWEEPS: tuple[Sweep, ...] = (
    Sweep("rom_addr_bits", (6, 8, 10, 12, 14), title="ROM-12 address bits"),
    Sweep("rom_data_bits", (8, 10, 12, 16), title="ROM-12 data bits"),
    Sweep("z_frac_bits", (6, 8, 10, 12, 16, 20, 26, 30), title="angle fraction bits"),
    Sweep("k_set", tuple(K_SETS), title="k-set (cos^k tables)"),
    Sweep("alpha", ("taylor", "inflection"), title="alpha mode (how a is chosen)"),
    Sweep("recip_bits", (10, 12, 14, 16, 18, 20), title="divider reciprocal bits N"),
    Sweep("p", (2, 4, 8, 16), title="Gouraud segment size P"),
    Sweep("specular_mode", ("unit", "adaptive", "vertex"), title="specular path"),
    Sweep(
        "highlight_levels",
        (0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0),
        base=(("specular_mode", "adaptive"),),
        title="adaptive highlight threshold (levels)",
    ),
)
"""One knob at a time around the default (each knob's effect isolated); the named alternatives
(the prototype's cos^2, a single cos^16, {1, 2, 16}, inflection, Gouraud only, adaptive) are
values of these sweeps."""

NAMED: dict[str, dict[str, object]] = {
    "free": {"alpha": "inflection", "specular_mode": "adaptive"},
    "scene-sized": {
        "alpha": "inflection",
        "specular_mode": "adaptive",
        "rom_addr_bits": 10,
        "rom_data_bits": 12,
        "recip_bits": 14,
    },
}
"""Knob combinations: the two changes that cost nothing ("free"), and a unit sized for what the
built-in scenes need rather than for the worst case (2047-pixel lines, every n)."""

FULL_PRODUCT: dict[str, tuple] = {
    "rom_addr_bits": (8, 10, 12),
    "rom_data_bits": (10, 12, 16),
    "z_frac_bits": (18, 22, 26),
    "k_set": tuple(K_SETS),
    "alpha": ("taylor", "inflection"),
    "recip_bits": (14, 20),
}
"""The full grid adds this cross product (432 configurations: interactions of the knobs)."""

GRIDS = ("small", "full")


def grid_configs(grid: str = "small") -> list[dict[str, object]]:
    """Knob overrides of every configuration of the grid, in order, without repeats."""
    scene.check_choice("grid", grid, GRIDS)
    configs = [{}] + [c for s in SMALL_SWEEPS for c in s.configs()] + list(NAMED.values())
    if grid == "full":
        names = list(FULL_PRODUCT)
        configs += [
            dict(zip(names, vals, strict=True))
            for vals in itertools.product(*FULL_PRODUCT.values())
        ]
    seen: set[str] = set()
    unique = []
    for c in configs:
        key = DEFAULT_POINT.with_knobs(**c).config_key
        if key not in seen:
            seen.add(key)
            unique.append(c)
    return unique


def grid_points(
    grid: str = "small", scenes: Sequence[str] = scene.SCENE_NAMES, size: int = DEFAULT_SIZE
) -> list[TradePoint]:
    """Every (configuration, scene) of the grid; each configuration is validated here."""
    points = []
    for c in grid_configs(grid):
        for s in scenes:
            p = TradePoint(scene=s, size=size, **c)
            p.to_pipeline_config()  # a bad configuration fails before anything is submitted
            points.append(p)
    return points


# ================================================================================ one point
@functools.lru_cache(maxsize=8)
def _scene_reference(scene_name: str, size: int):
    """Rasterise once per process; the exact reference (a) and its highlight mask."""
    frame_raster = raster.rasterise(scene.builtin_scene(scene_name, size, size))
    ref = raster.shade(frame_raster, reference.exact_blinn)
    return frame_raster, ref, metrics.highlight_mask(ref.specular)


@functools.lru_cache(maxsize=64)
def epicentre_error(cfg: specular.SpecularConfig) -> tuple[float, int, float, float]:
    """(worst relative error of the ROM-12 path vs cos^n over n = 2..1000, at n, worst output
    error vs C cos^n in LSBs over n = 1..1000, the unit's own worst error vs its float
    approximation C cos^k(a zeta) in LSBs): ``specular.fixed_point_accuracy`` (exhaustive over
    every angle register value, C at full scale), once per configuration.

    n = 1 is left out of the relative figure: its epicentre runs down to cos = 0, where a
    relative error measures how a tiny value is rounded (4.9 % at cos = 1/255 for every
    configuration with a 16-bit table) and would hide every knob; the LSB figure covers it.
    """
    acc = specular.fixed_point_accuracy(cfg)
    i = 1 + int(np.argmax(acc.rom_rel[1:]))
    return (
        float(acc.rom_rel[i]),
        i + 1,
        float(acc.out_lsb_exact.max()),
        float(acc.out_lsb_approx.max()),
    )


def line_drift(cfg: pipeline.PipelineConfig) -> float:
    """Worst drift (levels) of a line's end value over the longest line: the divider's
    reciprocal (|a| k / 2^(N+1), |a| <= 255, k = k_max) plus the rounded increment
    (``gouraud.drift_bound``)."""
    d = cfg.divider
    return 255.0 * d.k_max / 2.0 ** (d.recip_bits + 1) + gouraud.drift_bound(cfg.gouraud)


def angle_drift(cfg: pipeline.PipelineConfig) -> float:
    """Worst error of the accumulated angle at the end of the longest line, in ROM-12 address
    steps: dz and z0 rounded to 2^-(z_frac_bits+1) each, 2^len_width of them, scaled by the
    largest a (the angle-fraction figure the sampled epicentre error cannot show)."""
    s = cfg.specular
    a_max = float(specular.rom9_words(s).max()) / 2.0**s.a_frac_bits
    return 2.0**s.len_width * 2.0 ** -(s.z_frac_bits + 1) * a_max * 2.0**s.rom_addr_bits


def hardware(cfg: pipeline.PipelineConfig) -> dict[str, int]:
    """Adders, multipliers and multiplier partial-product bits (counting rule: module doc)."""
    has_spec = cfg.specular_mode != "vertex"
    s = cfg.specular
    return {
        "adders": CHANNELS * (1 + gouraud.adder_counts(cfg.gouraud.p)["total"]) + int(has_spec),
        "multipliers": 2 * int(has_spec),
        "mult_bits": (s.mag_width * s.a_width + s.c_width * s.rom_data_bits) * int(has_spec),
    }


def evaluate(point: TradePoint, repeats: int = 3) -> dict[str, object]:
    """Render the point's scene through its configuration; accuracy and cost (a flat dict)."""
    cfg = point.to_pipeline_config()
    frame_raster, ref, highlight = _scene_reference(point.scene, point.size)
    shader = pipeline.unit_shader(cfg)
    raster.shade(frame_raster, shader)  # warm-up: numba compiles or loads on the first call
    best, frame = math.inf, None
    for _ in range(max(1, repeats)):
        frame = raster.shade(frame_raster, shader)
        best = min(best, frame.stats.shade_seconds)
    cmp = metrics.compare(frame.rgb, ref.rgb, highlight=highlight)
    k = frame.stats.counters
    pixels = frame.stats.pixels_shaded
    div_c, gou_c, spec_c = (
        int(k.get("divider_cycles", 0)),
        int(k.get("gouraud_cycles", 0)),
        int(k.get("specular_cycles", 0)),
    )
    cycles = div_c + gou_c + spec_c
    frame_clocks = max(math.ceil(div_c / CHANNELS), math.ceil(gou_c / CHANNELS), spec_c)
    if cfg.specular_mode == "vertex":
        epi, epi_n, epi_lsb, unit_lsb = math.nan, 0, math.nan, math.nan
    else:
        epi, epi_n, epi_lsb, unit_lsb = epicentre_error(cfg.specular)
    return {
        **dataclasses.asdict(point),
        "key": point.key,
        "config_key": point.config_key,
        "label": point.label,
        "nmse": cmp.nmse,
        "psnr": cmp.psnr,
        "max_abs_error": cmp.max_abs_error,
        "share_off_by_more_than_1": cmp.share_off_by_more_than_1,
        "highlight_max_abs_error": cmp.highlight_max_abs_error,
        "epicentre_rel_error": epi,
        "epicentre_worst_n": epi_n,
        "epicentre_out_lsb": epi_lsb,
        "unit_error_lsb": unit_lsb,
        "line_drift_levels": line_drift(cfg),
        "angle_drift_steps": angle_drift(cfg) if cfg.specular_mode != "vertex" else math.nan,
        "pixels_shaded": pixels,
        "divider_cycles": div_c,
        "gouraud_cycles": gou_c,
        "specular_cycles": spec_c,
        "specular_pixels": int(k.get("specular_pixels", 0)),
        "cycles": cycles,
        "frame_clocks": frame_clocks,
        "px_per_clock": pixels / max(cycles, 1),
        "px_per_clock_parallel": pixels / max(frame_clocks, 1),
        "table_bits": report.table_bits("trade", cfg),
        **hardware(cfg),
        "shade_seconds": best,
        "sw_pixels_per_second": pixels / max(best, 1e-12),
    }


# ================================================================================ the cache
def cache_path(cache_dir: Path, point: TradePoint) -> Path:
    return Path(cache_dir) / f"{point.key}.json"


_COUNT = ("int", 0, math.inf, False)
_SIZE = ("float", 0.0, math.inf, False)
RESULT_RANGES: dict[str, tuple[str, float, float, bool]] = {
    "nmse": _SIZE,
    "psnr": ("float", 0.0, math.inf, False),  # +inf: equal to the reference
    "max_abs_error": ("float", 0.0, 255.0, False),
    "share_off_by_more_than_1": ("float", 0.0, 1.0, False),
    "highlight_max_abs_error": ("float", 0.0, 255.0, True),
    "epicentre_rel_error": ("float", 0.0, math.inf, True),
    "epicentre_worst_n": ("int", 0, specular.N_MAX, False),
    "epicentre_out_lsb": ("float", 0.0, math.inf, True),
    "unit_error_lsb": ("float", 0.0, math.inf, True),
    "line_drift_levels": _SIZE,
    "angle_drift_steps": ("float", 0.0, math.inf, True),
    **dict.fromkeys(
        ("pixels_shaded", "divider_cycles", "gouraud_cycles", "specular_cycles"), _COUNT
    ),
    **dict.fromkeys(("specular_pixels", "cycles", "frame_clocks", "table_bits"), _COUNT),
    **dict.fromkeys(("adders", "multipliers", "mult_bits"), _COUNT),
    **dict.fromkeys(("px_per_clock", "px_per_clock_parallel", "shade_seconds"), _SIZE),
    "sw_pixels_per_second": _SIZE,
}
"""Every figure of a result (``evaluate``): kind, legal range, NaN allowed (no specular unit, no
highlight pixel).  A cached result is used only when every one is present and legal."""


def check_result(point: TradePoint, result) -> str | None:
    """Why ``result`` is not a valid result of ``point`` (a missing field, a figure out of
    range, another point's fields), or None when it is."""
    if not isinstance(result, dict):
        return f"result is a {type(result).__name__}, not an object"
    expect = {**dataclasses.asdict(point), "key": point.key, "config_key": point.config_key}
    for name, value in expect.items():
        if name not in result:
            return f"field {name!r} is missing"
        if result[name] != value:
            return f"{name} = {result[name]!r} is not this point's {value!r}"
    if not isinstance(result.get("label"), str):
        return "field 'label' is missing or not a string"
    for name, (kind, lo, hi, nan_ok) in RESULT_RANGES.items():
        if name not in result:
            return f"field {name!r} is missing"
        x = result[name]
        number = int | float if kind == "float" else int
        legal = "an integer" if kind == "int" else "a finite number"
        legal += f" >= {lo:g}" if math.isinf(hi) else f" in {lo:g}..{hi:g}"
        if name == "psnr":
            legal += " (inf: equal images)"
        if nan_ok:
            legal += " or NaN"
        if isinstance(x, bool) or not isinstance(x, number):
            return f"{name} = {x!r} is not legal: legal is {legal}"
        if math.isnan(x) and nan_ok:
            continue
        if math.isnan(x) or not lo <= x <= hi or (math.isinf(x) and name != "psnr"):
            return f"{name} = {x!r} is out of range: legal is {legal}"
    return None


def read_cached(cache_dir: Path, point: TradePoint) -> tuple[dict | None, str | None]:
    """(the cached result of the point, None), (None, None) when there is no cache file, or
    (None, why) when the file is there but cannot be used (broken, another point's, invalid)."""
    path = cache_path(cache_dir, point)
    try:
        text = path.read_text()
    except FileNotFoundError:
        return None, None
    except (OSError, UnicodeDecodeError) as exc:
        return None, f"unreadable: {exc}"
    try:
        data = json.loads(text)
    except ValueError as exc:
        return None, f"not valid JSON: {exc}"
    if not isinstance(data, dict):
        return None, f"holds a JSON {type(data).__name__}, not an object"
    if data.get("version") != CACHE_VERSION:
        return None, f"version = {data.get('version')!r}, expected {CACHE_VERSION}"
    if data.get("point") != dataclasses.asdict(point):
        return None, "holds the result of another point"
    why = check_result(point, data["result"]) if "result" in data else "field 'result' is missing"
    if why is not None:
        return None, why
    return data["result"], None


def load_cached(cache_dir: Path, point: TradePoint) -> dict | None:
    """The cached result of the point, or None (missing, unreadable, of another point or
    invalid: ``read_cached`` says why)."""
    return read_cached(cache_dir, point)[0]


def store(cache_dir: Path, point: TradePoint, result: dict) -> Path:
    """Write the result atomically: a temporary file in the cache folder, then os.replace."""
    path = cache_path(cache_dir, point)
    path.parent.mkdir(parents=True, exist_ok=True)
    payload = {"version": CACHE_VERSION, "point": dataclasses.asdict(point), "result": result}
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{point.key}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(payload, f, indent=1)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


# ================================================================================ the engine
@dataclass(frozen=True)
class SweepOutcome:
    results: list[dict]  # in the order of the points given
    cached: int  # points found in the cache
    evaluated: int  # points evaluated (submitted) in this run
    failed: dict[str, str] = field(default_factory=dict)  # key -> error
    seconds: float = 0.0
    recomputed: dict[str, str] = field(default_factory=dict)  # key -> why its cache was unused


CONNECT_TIMEOUT = 5.0
"""Seconds to wait for ``--scheduler`` before giving up (Dask's own default is 30)."""
LOCK_NAME = "sweep.lock"
"""The lock file in the cache folder: one sweep at a time per cache (``sweep_lock``)."""
SetupError = report.SetupError


def check_workers(workers, allow_zero: bool = False) -> int | None:
    """``workers`` as an int (None: the default), or ``ValueError`` naming it (a negative count
    made the LocalCluster hang)."""
    lo = 0 if allow_zero else 1
    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, int | np.integer) or workers < lo:
        extra = " (0: evaluate in this process)" if allow_zero else ""
        raise ValueError(
            f"workers = {workers!r} is out of range: legal is None (local default) or an "
            f"integer >= {lo}{extra}"
        )
    return int(workers)


def connect(scheduler: str, timeout: float = CONNECT_TIMEOUT):
    """A client of the Dask scheduler at ``scheduler``, or ``SetupError`` naming the address
    after ``timeout`` seconds (unreachable) or at once (not an address)."""
    from dask.distributed import Client

    try:
        return Client(scheduler, timeout=timeout)
    except (OSError, ValueError, TypeError) as exc:
        why = f"no answer within {timeout:g} s" if isinstance(exc, OSError) else str(exc)
        raise SetupError(
            f"argument --scheduler: cannot connect to {scheduler!r} ({why}): must be the "
            "address of a running Dask scheduler, e.g. tcp://127.0.0.1:8786",
            status=1,
        ) from None


@contextlib.contextmanager
def sweep_lock(cache_dir: Path):
    """Hold ``<cache_dir>/sweep.lock`` (``fcntl.flock``, released when the process ends, even
    killed) for one sweep; a second sweep on the same cache does not wait: it raises
    ``SetupError`` naming the lock file and the pid that holds it."""
    import fcntl

    path = Path(cache_dir) / LOCK_NAME
    path.parent.mkdir(parents=True, exist_ok=True)
    f = open(path, "a+")  # noqa: SIM115 (held open for the whole with-block)
    try:
        fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        f.seek(0)
        other = f.read().strip() or "unknown"
        f.close()
        raise SetupError(
            f"another trade sweep (pid {other}) holds the lock {path}: one sweep at a time per "
            "--out; wait for it to finish or use another --out",
            status=1,
        ) from None
    try:
        f.seek(0)
        f.truncate()
        f.write(f"{os.getpid()}\n")
        f.flush()
        yield path
    finally:
        f.truncate(0)
        fcntl.flock(f, fcntl.LOCK_UN)
        f.close()


def make_client(workers: int | None = None, scheduler: str | None = None):
    """A Dask client: to the scheduler at ``scheduler`` (``connect``), or a LocalCluster of
    ``workers`` processes (>= 1; default min(2, CPUs))."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        return connect(scheduler)
    n = check_workers(workers) or min(2, os.cpu_count() or 1)
    cluster = LocalCluster(
        n_workers=n,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=40,  # logging.ERROR
    )
    return Client(cluster)


def run_sweep(
    points: Iterable[TradePoint],
    cache_dir: Path,
    *,
    client=None,
    workers: int | None = None,
    scheduler: str | None = None,
    repeats: int = 3,
    progress: bool = True,
    evaluate_fn: Callable[..., dict] = evaluate,
    lock: bool = True,
) -> SweepOutcome:
    """Evaluate every point not in ``cache_dir`` on Dask and cache each result as it comes.

    ``client``: an existing ``dask.distributed.Client`` (kept open); otherwise one is made from
    ``scheduler`` / ``workers`` and closed at the end.  ``workers=0`` without a client or
    scheduler evaluates in this process, in order (debugging, ``NUMBA_DISABLE_JIT=1``).
    A cache file that cannot be used (broken JSON, not an object, a missing field, a figure out
    of range: ``read_cached``) is evaluated again, and said so (one line each with
    ``progress``; ``SweepOutcome.recomputed``).  ``lock``: hold ``sweep_lock(cache_dir)`` for
    the sweep (a second sweep on the same cache raises ``SetupError`` at once).
    """
    check_workers(workers, allow_zero=True)
    cache_dir = Path(cache_dir)
    cache_dir.mkdir(parents=True, exist_ok=True)
    with sweep_lock(cache_dir) if lock else contextlib.nullcontext():
        return _run_sweep(
            points, cache_dir, client, workers, scheduler, repeats, progress, evaluate_fn
        )


def _run_sweep(
    points, cache_dir, client, workers, scheduler, repeats, progress, evaluate_fn
) -> SweepOutcome:
    from tqdm import tqdm

    began = time.perf_counter()
    points = list(dict.fromkeys(points))  # unique, in order
    done: dict[str, dict] = {}
    recomputed: dict[str, str] = {}
    for p in points:
        cached, why = read_cached(cache_dir, p)
        if cached is not None:
            done[p.key] = cached
        elif why is not None:
            recomputed[p.key] = why
            if progress:
                print(
                    f"trade: cache entry {cache_path(cache_dir, p)} is not used ({why}): "
                    "evaluating the point again"
                )
    todo = [p for p in points if p.key not in done]
    n_cached = len(done)
    if progress:
        print(f"trade: {len(points)} points, {n_cached} cached, {len(todo)} to evaluate")
    failed: dict[str, str] = {}
    bar = tqdm(total=len(todo), desc="trade", unit="pt", disable=not progress or not todo)

    def finish(p: TradePoint, result: dict) -> None:
        store(cache_dir, p, result)
        done[p.key] = result
        bar.update(1)

    if todo and client is None and scheduler is None and workers == 0:
        for p in todo:
            try:
                finish(p, evaluate_fn(p, repeats))
            except Exception as exc:
                failed[p.key] = f"{p}: {exc!r}"
    elif todo:
        from dask.distributed import as_completed

        own = client is None
        client = client or make_client(workers, scheduler)
        try:
            futures = {
                client.submit(evaluate_fn, p, repeats, key=f"trade-{p.key}", pure=False): p
                for p in todo
            }
            for fut in as_completed(futures):
                p = futures[fut]
                try:
                    finish(p, fut.result())
                except Exception as exc:
                    failed[p.key] = f"{p}: {exc!r}"
                fut.release()
        finally:
            if own:
                cluster = client.cluster
                client.close()
                if cluster is not None:
                    cluster.close()
    bar.close()
    return SweepOutcome(
        results=[done[p.key] for p in points if p.key in done],
        cached=n_cached,
        evaluated=len(todo),
        failed=failed,
        seconds=time.perf_counter() - began,
        recomputed=recomputed,
    )


# ================================================================================ analysis
def pareto_mask(objectives: np.ndarray) -> np.ndarray:
    """(m,) bool: rows no other row dominates (<= in every column, < in one); all minimised."""
    obj = np.asarray(objectives, dtype=np.float64)
    m = obj.shape[0]
    mask = np.ones(m, dtype=bool)
    for i in range(m):
        le = np.all(obj <= obj[i], axis=1)
        lt = np.any(obj < obj[i], axis=1)
        if np.any(le & lt):
            mask[i] = False
    return mask


def eps_dominates(a: Sequence[float], b: Sequence[float], eps: float = NEAR) -> bool:
    """True when ``a`` beats ``b`` by more than a factor (1 + eps) in one objective while it is
    no worse than a factor (1 + eps) in every other (all objectives minimised, positive).

    "``b`` is near the front" means no point eps-dominates it: nothing is markedly better in one
    figure without being markedly worse in another."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    tol = 1.0 + eps
    return bool(np.all(a <= b * tol) and np.any(a * tol < b))


def near_front(objectives: np.ndarray, index: int, eps: float = NEAR) -> list[int]:
    """Rows that eps-dominate row ``index`` (empty: it is on or near the front)."""
    obj = np.asarray(objectives, dtype=np.float64)
    return [j for j in range(obj.shape[0]) if j != index and eps_dominates(obj[j], obj[index], eps)]


SUM_FIELDS = ("cycles", "frame_clocks", "pixels_shaded", "shade_seconds", "specular_pixels")


def aggregate(results: list[dict]) -> list[dict]:
    """One row per configuration (in first-seen order): the scenes' mean NMSE, worst PSNR and
    max error, mean cycles and frame clocks per frame, pooled pixels per clock and per second."""
    groups: dict[str, list[dict]] = {}
    for r in results:
        groups.setdefault(r["config_key"], []).append(r)
    rows = []
    for rs in groups.values():
        first = rs[0]
        row = {k: first[k] for k in (*KNOBS, "config_key", "label")}
        tot = {f: sum(r[f] for r in rs) for f in SUM_FIELDS}
        row.update(
            scenes=",".join(r["scene"] for r in rs),
            size=first["size"],
            nmse=float(np.mean([r["nmse"] for r in rs])),
            psnr=float(min(r["psnr"] for r in rs)),
            max_abs_error=float(max(r["max_abs_error"] for r in rs)),
            highlight_max_abs_error=float(np.nanmax([r["highlight_max_abs_error"] for r in rs])),
            epicentre_rel_error=first["epicentre_rel_error"],
            epicentre_worst_n=first["epicentre_worst_n"],
            unit_error_lsb=first["unit_error_lsb"],
            line_drift_levels=first["line_drift_levels"],
            angle_drift_steps=first["angle_drift_steps"],
            cycles=tot["cycles"] / len(rs),
            frame_clocks=tot["frame_clocks"] / len(rs),
            px_per_clock=tot["pixels_shaded"] / max(tot["cycles"], 1),
            px_per_clock_parallel=tot["pixels_shaded"] / max(tot["frame_clocks"], 1),
            specular_share=tot["specular_pixels"] / max(tot["pixels_shaded"], 1),
            table_bits=first["table_bits"],
            adders=first["adders"],
            multipliers=first["multipliers"],
            mult_bits=first["mult_bits"],
            sw_pixels_per_second=tot["pixels_shaded"] / max(tot["shade_seconds"], 1e-12),
        )
        rows.append(row)
    objectives = {
        "cycles": np.array([[r["nmse"], r["cycles"]] for r in rows]),
        "bits": np.array([[r["nmse"], r["table_bits"]] for r in rows]),
    }
    for name, obj in objectives.items():
        for r, on in zip(rows, pareto_mask(obj), strict=True):
            r[f"pareto_{name}"] = bool(on)
    return rows


def default_row(rows: list[dict]) -> int | None:
    for i, r in enumerate(rows):
        if r["label"] == "default":
            return i
    return None


def worst_figures(r: dict) -> list[float]:
    """The worst-case unit figures (NaN = no specular unit: counted as infinitely bad)."""
    return [
        r["epicentre_rel_error"],
        r["unit_error_lsb"],
        r["line_drift_levels"],
        r["angle_drift_steps"],
    ]


ALL_COSTS = ("cycles", "table_bits", "adders", "mult_bits")


def front_objectives(rows: list[dict]) -> dict[str, np.ndarray]:
    """The fronts the study reports, all figures minimised: NMSE against cycles, NMSE against
    table bits, and "all": NMSE, the worst-case unit figures and every cost at once."""
    worst = np.array([worst_figures(r) for r in rows], dtype=np.float64).reshape(len(rows), 4)
    worst = np.nan_to_num(worst, nan=np.inf)
    nmse = np.array([[r["nmse"]] for r in rows], dtype=np.float64).reshape(len(rows), 1)
    costs = np.array([[r[c] for c in ALL_COSTS] for r in rows], dtype=np.float64)
    return {
        "cycles": np.hstack([nmse, costs[:, :1]]),
        "table bits": np.hstack([nmse, costs[:, 1:2]]),
        "all figures": np.hstack([nmse, worst, costs]),
    }


def default_position(rows: list[dict], eps: float = NEAR) -> dict[str, list[str]]:
    """For each front (``front_objectives``): labels of the configurations that eps-dominate
    the default (empty: the default is on or near that front)."""
    d = default_row(rows)
    if d is None:
        return {}
    return {
        name: [rows[j]["label"] for j in near_front(obj, d, eps)]
        for name, obj in front_objectives(rows).items()
    }


# ================================================================================ outputs
CSV_FIELDS = (
    "scene",
    "size",
    *KNOBS,
    "label",
    "nmse",
    "psnr",
    "max_abs_error",
    "share_off_by_more_than_1",
    "highlight_max_abs_error",
    "epicentre_rel_error",
    "epicentre_worst_n",
    "epicentre_out_lsb",
    "unit_error_lsb",
    "line_drift_levels",
    "angle_drift_steps",
    "pixels_shaded",
    "divider_cycles",
    "gouraud_cycles",
    "specular_cycles",
    "specular_pixels",
    "cycles",
    "frame_clocks",
    "px_per_clock",
    "px_per_clock_parallel",
    "table_bits",
    "adders",
    "multipliers",
    "mult_bits",
    "shade_seconds",
    "sw_pixels_per_second",
    "key",
    "config_key",
)


def write_csv(results: list[dict], path: Path) -> Path:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_FIELDS, extrasaction="ignore")
        w.writeheader()
        w.writerows(results)
    return path


def _num(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{x:.3f}"


def _pct(x: float) -> str:
    return "-" if not np.isfinite(x) else f"{100 * x:.2f} %"


TABLE_HEAD = (
    "| config | NMSE (mean) | PSNR dB (min) | max err | epicentre err (n) | unit err (LSB) "
    "| line drift "
    "| angle drift | cycles/frame | frame clocks | px/clk | px/clk par. | table bits | adders "
    "| mult (bits) | Mpx/s | front |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
)


def table_row(r: dict) -> str:
    marks = ("C" if r["pareto_cycles"] else "") + ("B" if r["pareto_bits"] else "")
    epi = (
        f"{_pct(r['epicentre_rel_error'])} ({r['epicentre_worst_n']})"
        if np.isfinite(r["epicentre_rel_error"])
        else "-"
    )
    name = "**default**" if r["label"] == "default" else r["label"]
    return (
        f"| {name} | {r['nmse']:.6f} | {r['psnr']:.1f} | {r['max_abs_error']:.0f} | {epi} "
        f"| {_num(r['unit_error_lsb'])} "
        f"| {r['line_drift_levels']:.3f} | {_num(r['angle_drift_steps'])} "
        f"| {r['cycles']:,.0f} | {r['frame_clocks']:,.0f} "
        f"| {r['px_per_clock']:.3f} | {r['px_per_clock_parallel']:.3f} | {r['table_bits']:,} "
        f"| {r['adders']} | {r['multipliers']} ({r['mult_bits']}) "
        f"| {r['sw_pixels_per_second'] / 1e6:.2f} | {marks or '-'} |"
    )


def sweep_rows(sweep: Sweep, rows: list[dict]) -> list[dict]:
    """The aggregated rows of the sweep's configurations, in the sweep's order."""
    by_knobs = {tuple(r[k] for k in KNOBS): r for r in rows}
    out = []
    for c in sweep.configs():
        knobs = {**DEFAULT_POINT.knobs, **c}
        r = by_knobs.get(tuple(knobs[k] for k in KNOBS))
        if r is not None:
            out.append(r)
    return out


def _ratio(a: float, b: float) -> str:
    return f"{a / b:.2f}x" if b else "-"


def knob_summary(sweep: Sweep, rows: list[dict]) -> str:
    """What the knob buys, from its one-knob sweep: accuracy and cost at each end."""
    rs = sweep_rows(sweep, rows)
    if len(rs) < 2:
        return f"* {sweep.title}: not measured"
    base = {**DEFAULT_POINT.knobs, **dict(sweep.base)}
    ref = next((r for r in rs if r[sweep.knob] == base[sweep.knob]), rs[0])
    parts = []
    for r in rs:
        if r is ref:
            continue
        parts.append(
            f"{r[sweep.knob]}: NMSE {_ratio(r['nmse'], ref['nmse'])}, epicentre "
            f"{_pct(r['epicentre_rel_error'])}, cycles {_ratio(r['cycles'], ref['cycles'])}, "
            f"frame clocks {_ratio(r['frame_clocks'], ref['frame_clocks'])}, table bits "
            f"{_ratio(r['table_bits'], ref['table_bits'])}"
        )
    return (
        f"* **{sweep.title}** (`{sweep.knob}`, against {ref[sweep.knob]}: NMSE "
        f"{ref['nmse']:.6f}, epicentre {_pct(ref['epicentre_rel_error'])}): " + "; ".join(parts)
    )


def format_markdown(rows: list[dict], sweeps: Sequence[Sweep] = SMALL_SWEEPS) -> str:
    lines = ["# Speed/accuracy trade", ""]
    if rows:
        lines.append(
            f"Scenes: {rows[0]['scenes']} at {rows[0]['size']} x {rows[0]['size']}; accuracy "
            "against exact Blinn (a): NMSE mean, PSNR and max error worst over the scenes; "
            "cost per frame: mean over the scenes.  front: C = on the NMSE-vs-cycles Pareto "
            "front, B = on the NMSE-vs-table-bits front (over every configuration of the run)."
        )
        lines.append("")
    shown: set[str] = set()
    for sw in sweeps:
        rs = sweep_rows(sw, rows)
        if not rs:
            continue
        lines += [f"## {sw.title} (`{sw.knob}`)", "", TABLE_HEAD]
        lines += [table_row(r) for r in rs]
        lines.append("")
        shown.update(r["config_key"] for r in rs)
    rest = [r for r in rows if r["config_key"] not in shown]
    if rest:
        lines += ["## other configurations", "", TABLE_HEAD, *map(table_row, rest), ""]
    lines += ["## What each knob buys", ""]
    lines += [knob_summary(sw, rows) for sw in sweeps]
    lines += ["", "## Where the default lies", ""]
    for name, labels in default_position(rows).items():
        verdict = "on or near the front" if not labels else "eps-dominated by " + "; ".join(labels)
        lines.append(f"* NMSE vs {name}: {verdict}")
    lines.append(
        f"\n(eps-dominated: another configuration is more than {100 * NEAR:.0f} % better in one "
        f"figure and at most {100 * NEAR:.0f} % worse in every other; all figures: NMSE, the "
        "worst epicentre error, line drift and angle drift, cycles, table bits, adders and "
        "multiplier bits.)"
    )
    return "\n".join(lines) + "\n"


def plot_pareto(rows: list[dict], x: str, path: Path, ax=None) -> Path | None:
    """NMSE (log) against ``x`` ("cycles" or "table_bits"), the front and the default marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    front_key = "pareto_cycles" if x == "cycles" else "pareto_bits"
    xlabel = "unit cycles per frame (mean over scenes)" if x == "cycles" else "ROM bits"
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=100)
    xs = np.array([r[x] for r in rows], dtype=float)
    ys = np.array([r["nmse"] for r in rows], dtype=float)
    front = np.array([r[front_key] for r in rows])
    knob = [DEFAULT_POINT.with_knobs(**_knobs(r)).group for r in rows]
    kinds = sorted(set(knob) - {"default"})
    cmap = plt.get_cmap("tab10")
    for i, kname in enumerate(kinds):
        sel = np.array([k == kname for k in knob])
        ax.scatter(xs[sel], ys[sel], s=18, color=cmap(i % 10), label=kname, alpha=0.8)
    order = np.argsort(xs[front])
    ax.plot(xs[front][order], ys[front][order], "k--", lw=1, label="Pareto front")
    ax.scatter(xs[front], ys[front], s=60, facecolors="none", edgecolors="k")
    d = default_row(rows)
    if d is not None:
        ax.scatter([xs[d]], [ys[d]], s=140, marker="*", color="red", zorder=5, label="default")
    ax.axhline(metrics.NMSE_VISUALLY_IDENTICAL, color="grey", lw=0.8, ls=":")
    ax.set_yscale("log")
    if x == "table_bits":
        ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("NMSE vs exact Blinn (mean over scenes)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, loc="upper right", ncol=2)
    if own:
        fig.tight_layout()
        fig.savefig(path)
        plt.close(fig)
        return path
    return None


def _knobs(r: dict) -> dict:
    return {k: r[k] for k in KNOBS}


def plot_figure(rows: list[dict], path: Path) -> Path:
    """Both fronts side by side, small (the README's committed figure)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), dpi=80)
    plot_pareto(rows, "cycles", path, ax=axes[0])
    plot_pareto(rows, "table_bits", path, ax=axes[1])
    axes[0].set_title("NMSE against unit cycles per frame")
    axes[1].set_title("NMSE against ROM bits")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path


def write_outputs(
    results: list[dict], out_dir: Path, figure_dir: Path | None = None
) -> tuple[list[dict], list[Path]]:
    """results.csv, results.md, pareto_cycles.png, pareto_bits.png (+ figure_dir's PNG)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = aggregate(results)
    written = [write_csv(results, out_dir / "results.csv")]
    md = out_dir / "results.md"
    md.write_text(format_markdown(rows))
    written.append(md)
    if rows:
        written.append(plot_pareto(rows, "cycles", out_dir / "pareto_cycles.png"))
        written.append(plot_pareto(rows, "table_bits", out_dir / "pareto_bits.png"))
        if figure_dir is not None:
            written.append(plot_figure(rows, Path(figure_dir) / "trade_pareto.png"))
    return rows, written


# ================================================================================ the command
def main(
    scenes: Sequence[str] = scene.SCENE_NAMES,
    size: int = DEFAULT_SIZE,
    grid: str = "small",
    out_dir: Path = DEFAULT_OUT,
    workers: int | None = None,
    scheduler: str | None = None,
    figure_dir: Path | None = None,
    repeats: int = 3,
    connect_timeout: float = CONNECT_TIMEOUT,
) -> int:
    """``python -m model trade``: sweep, cache, write the outputs, print the summary.

    Before any work (``SetupError``, named after the command-line arguments): ``out_dir`` and
    ``figure_dir`` must be folders this user can create and write in, the sweep lock of
    ``out_dir/cache`` must be free (a second sweep on the same ``--out`` is refused, it does not
    wait) and ``scheduler`` must answer within ``connect_timeout`` seconds."""
    workers = check_workers(workers, allow_zero=True)
    points = grid_points(grid, scenes, size)
    out_dir = report.check_output_dir("--out", Path(out_dir))
    cache_dir = report.check_output_dir("--out", out_dir / "cache")
    if figure_dir is not None:
        report.check_output_dir("--figure", Path(figure_dir))
    with sweep_lock(cache_dir):
        client = connect(scheduler, connect_timeout) if scheduler else None
        try:
            return _main(points, scenes, size, grid, out_dir, workers, client, figure_dir, repeats)
        finally:
            if client is not None:
                client.close()


def _main(points, scenes, size, grid, out_dir, workers, client, figure_dir, repeats) -> int:
    began = time.perf_counter()
    n_cfg = len({p.config_key for p in points})
    print(
        f"== trade: grid {grid!r}, {n_cfg} configurations x {len(scenes)} scenes "
        f"({', '.join(scenes)}) at {size} x {size} =="
    )
    outcome = run_sweep(
        points,
        out_dir / "cache",
        client=client,
        workers=workers,
        repeats=repeats,
        lock=False,  # main holds it
    )
    rows, written = write_outputs(outcome.results, out_dir, figure_dir)
    print("\n== What each knob buys ==")
    print("\n".join(knob_summary(sw, rows) for sw in SMALL_SWEEPS))
    print("\n== Where the default lies ==")
    for name, labels in default_position(rows).items():
        print(f"NMSE vs {name}: " + ("on or near the front" if not labels else "; ".join(labels)))
    print(f"\nwrote {', '.join(str(p) for p in written)}")
    recomputed = (
        f" ({len(outcome.recomputed)} unusable cache entries)" if outcome.recomputed else ""
    )
    print(
        f"trade: {outcome.evaluated} evaluated{recomputed}, {outcome.cached} from the cache, "
        f"{len(outcome.failed)} failed; took {time.perf_counter() - began:.1f} s"
    )
    for key, err in outcome.failed.items():
        print(f"FAILED {key}: {err}")
    return 1 if outcome.failed else 0
