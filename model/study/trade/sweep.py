# SPDX-License-Identifier: Apache-2.0
"""Evaluating trade points: the figures of one point, the result cache and the Dask engine.

Owns ``evaluate`` (one point's accuracy and cost figures, a flat dict) with its helpers, the
cache (``cache_path``, ``RESULT_RANGES``, ``check_result``, ``read_cached``, ``load_cached``,
``store``) and the engine (``run_sweep``, ``SweepOutcome``, ``make_client``, ``connect``,
``check_workers``, ``sweep_lock``).  May import ``model.units``, ``model.render`` (``core``: the
shading core's clocks), ``model.study`` ``metrics`` and ``report``, ``model.study.trade.points``.
A point whose highlight goes through a BRDF unit gets that unit's figures
(``accuracy_figures``, ``hardware``, ``BRDF_ADDERS``) and no shading-core clocks.

Size: about 560 lines: a result's figures (``evaluate``), their legal ranges (``RESULT_RANGES``,
which the cache checks) and the engine that stores them are kept in step in one file.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import json
import math
import os
import tempfile
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from model.render import core, pipeline, raster, reference, shade
from model.render.scenefile import SceneSource
from model.study import metrics, report
from model.study.trade.points import CACHE_VERSION, TradePoint, point_scene
from model.units import brdf, gouraud, specular

CHANNELS = 3
"""Colour channels: one divider and one Gouraud unit each in the parallel picture."""


# ================================================================================ one point
@functools.lru_cache(maxsize=8)
def _scene_reference(scene_key: str, size: int, source: SceneSource | None):
    """Rasterise once per process; the exact reference (a) and its highlight mask."""
    files = {scene_key: source} if source is not None else None
    frame_raster = raster.rasterise(point_scene(TradePoint(scene=scene_key, size=size), files))
    ref = shade.shade(frame_raster, reference.exact_blinn)
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


@functools.lru_cache(maxsize=16)
def brdf_epicentre_error(cfg: brdf.FixedConfig) -> tuple[float, int]:
    """(worst relative error of the BRDF unit's output word F against cos^n over n = 2..1000,
    at n): ``brdf.fixed_accuracy``'s ``rel_cos`` (exhaustive over every angle register value
    of the epicentre where cos^n >= 1/255, as ``epicentre_error``'s; n = 1 left out for the same
    reason), once per configuration: the figure ``epicentre_error`` gives the patent's unit."""
    return brdf.fixed_accuracy(cfg).worst("rel_cos", 2)[:2]


BRDF_ADDERS: dict[str, int] = {
    "cosine_quadratic": 3,
    "quadratic": 3,
    "cubic": 5,
    "log2": 2,
    "piecewise": 25,
}
"""The datapath adders of each BRDF form's unit at its default widths, counted in its RTL as
``hardware`` counts the patent's (rtl/brdf_unit.v and rtl/brdf_<form>.v): the angle
accumulator, and the cosine-quadratic's 1 - m and 7n = 8n - n (once per line), the quadratic's
1 - w and 1 - m, the cubic's c = 1 - w, tau = 1 - r w, h = b2 tau + b1 and P = tau h + p0, the
log2's 2 - log2 u (its octave's carry from the table address's rounding is a rounding
increment), the piecewise form's the cubic's four, its bloom part's c = 1 - w, r w - 1 and
den = s2 + beta (r w - 1), and its divider's subtractor per quotient bit (out_bits + 1 = 17:
rtl/brdf_div.v; the quotient's rounding (a + 1) >> 1 is a rounding increment);
rounding increments, |zeta|'s negation, n - 1, clips and saturations and the partial-product
sums inside the split multipliers (rtl/brdf_mul.v) are not counted.  A form not here (its RTL
not yet counted) has NaN adders."""


def frame_clocks(counters: dict) -> int:
    """A frame's clocks with the units in parallel, ideal buffering (module ``trade`` docstring):
    one divider and one Gouraud unit per colour channel, one specular unit taking the highlight
    jobs and then the diffuse jobs (n = 1); a column beside the core's ``core_clocks``."""
    div_c, gou_c = int(counters.get("divider_cycles", 0)), int(counters.get("gouraud_cycles", 0))
    spec_c = int(counters.get("specular_cycles", 0)) + int(counters.get("diffuse_cycles", 0))
    return max(math.ceil(div_c / CHANNELS), math.ceil(gou_c / CHANNELS), spec_c)


def core_clocks(pixels: int, cfg: pipeline.PipelineConfig | None = None) -> float:
    """A frame's clocks through the shading core built for ``cfg`` (docs/core.md, "Timing"):
    ``core.core_cycles(pixels, cfg)`` = ``core.latency(cfg)`` + pixels (18 + pixels with the
    patent's highlight path, 20 to 39 + pixels with a BRDF form's), the count the RTL's stream
    bench measures clock for clock (tests/test_core.py); 0 for a frame without pixels; NaN for
    a configuration the core cannot build (``core.check_core``: a BRDF form without a pipe in
    the core)."""
    cfg = cfg or pipeline.PipelineConfig()
    try:
        core.check_core(cfg)
    except ValueError:
        return math.nan
    return core.core_cycles(pixels, cfg) if pixels > 0 else 0


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


def brdf_angle_drift(cfg: brdf.FixedConfig) -> float:
    """``angle_drift`` for a BRDF unit: the same accumulated error in angle-table address steps
    (the table is addressed by |zeta| itself: a = 1, ``cos_addr_bits`` address bits)."""
    a = cfg.angle
    return 2.0**a.len_width * 2.0 ** -(a.z_frac_bits + 1) * 2.0**cfg.cos_addr_bits


def hardware(cfg: pipeline.PipelineConfig) -> dict[str, float]:
    """Adders, multipliers and multiplier partial-product bits (counting rule: module doc); with
    a BRDF unit its own (``BRDF_ADDERS``, ``brdf.multipliers``: the form's two and C x F), NaN
    where its RTL is not counted."""
    div_gou = CHANNELS * (1 + gouraud.adder_counts(cfg.gouraud.p)["total"])
    if cfg.brdf is not None:
        try:
            mults = brdf.multipliers(cfg.brdf)
        except KeyError:  # a form whose data sheet does not count its multipliers yet
            return {"adders": math.nan, "multipliers": math.nan, "mult_bits": math.nan}
        adders = BRDF_ADDERS.get(cfg.brdf.form)
        return {
            "adders": math.nan if adders is None else div_gou + adders,
            "multipliers": len(mults),
            "mult_bits": sum(a * b for _, a, b in mults),
        }
    has_spec = cfg.uses_specular_unit
    s = cfg.specular
    return {
        "adders": div_gou + int(has_spec),
        "multipliers": 2 * int(has_spec),
        "mult_bits": (s.mag_width * s.a_width + s.c_width * s.rom_data_bits) * int(has_spec),
    }


def accuracy_figures(cfg: pipeline.PipelineConfig) -> dict[str, float]:
    """The configuration's exhaustive unit figures (module ``trade`` docstring): the patent
    unit's (``epicentre_error``, ``angle_drift``), a BRDF unit's (``brdf_epicentre_error``,
    ``brdf_angle_drift``; no LSB figures: ``brdf.fixed_accuracy`` measures the word F before
    x C), or NaN (no unit, or one that keeps only some n)."""
    nan = {"epicentre_rel_error": math.nan, "epicentre_worst_n": 0}
    nan |= {"epicentre_out_lsb": math.nan, "unit_error_lsb": math.nan}
    if cfg.brdf is not None:
        epi, epi_n = brdf_epicentre_error(cfg.brdf)
        return {
            **nan,
            "epicentre_rel_error": epi,
            "epicentre_worst_n": epi_n,
            "angle_drift_steps": brdf_angle_drift(cfg.brdf),
        }
    s = cfg.specular
    drift = {"angle_drift_steps": angle_drift(cfg) if cfg.uses_specular_unit else math.nan}
    if not cfg.uses_specular_unit or (s.n_first, s.n_last) != (1, specular.N_MAX):
        # No unit, or one that keeps only some n (a fitted one): no figure over n = 1..1000.
        return {**nan, **drift}
    epi, epi_n, epi_lsb, unit_lsb = epicentre_error(s)
    return {
        "epicentre_rel_error": epi,
        "epicentre_worst_n": epi_n,
        "epicentre_out_lsb": epi_lsb,
        "unit_error_lsb": unit_lsb,
        **drift,
    }


def evaluate(
    point: TradePoint, repeats: int = 3, sources: Mapping[str, SceneSource] | None = None
) -> dict[str, object]:
    """Render the point's scene through its configuration; accuracy and cost (a flat dict).

    ``sources``: the scene file or mesh file of each file key among the scenes
    (``points.point_scene``); the sweep passes it as ``functools.partial(evaluate,
    sources=...)``."""
    cfg = point.to_pipeline_config()
    frame_raster, ref, highlight = _scene_reference(
        point.scene, point.size, (sources or {}).get(point.scene)
    )
    shader = pipeline.unit_shader(cfg)
    shade.shade(frame_raster, shader)  # warm-up: numba compiles or loads on the first call
    best, frame = math.inf, None
    for _ in range(max(1, repeats)):
        frame = shade.shade(frame_raster, shader)
        best = min(best, frame.stats.shade_seconds)
    cmp = metrics.compare(frame.rgb, ref.rgb, highlight=highlight)
    k = frame.stats.counters
    pixels = frame.stats.pixels_shaded
    div_c, gou_c, spec_c, diff_c = (
        int(k.get("divider_cycles", 0)),
        int(k.get("gouraud_cycles", 0)),
        int(k.get("specular_cycles", 0)),
        int(k.get("diffuse_cycles", 0)),
    )
    cycles = div_c + gou_c + spec_c + diff_c
    clocks = frame_clocks(k)
    # The shading core with the configuration's highlight path (a BRDF form's pipe: its latency)
    on_core = core_clocks(pixels, cfg)
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
        **accuracy_figures(cfg),
        "line_drift_levels": line_drift(cfg),
        "pixels_shaded": pixels,
        "divider_cycles": div_c,
        "gouraud_cycles": gou_c,
        "specular_cycles": spec_c,
        "specular_pixels": int(k.get("specular_pixels", 0)),
        "diffuse_cycles": diff_c,
        "diffuse_pixels": int(k.get("diffuse_pixels", 0)),
        "cycles": cycles,
        "frame_clocks": clocks,
        "px_per_clock": pixels / max(cycles, 1),
        "px_per_clock_parallel": pixels / max(clocks, 1),
        "core_clocks": on_core,
        "px_per_clock_core": pixels / max(on_core, 1) if math.isfinite(on_core) else math.nan,
        "table_bits": report.table_bits("trade", cfg),
        **hardware(cfg),
        "shade_seconds": best,
        "sw_pixels_per_second": pixels / max(best, 1e-12),
    }


# ================================================================================ the cache
def cache_path(cache_dir: Path, point: TradePoint) -> Path:
    return Path(cache_dir) / f"{point.key}.json"


_COUNT = ("int", 0, math.inf, False)
_COUNT_NAN = ("int", 0, math.inf, True)
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
    **dict.fromkeys(("diffuse_cycles", "diffuse_pixels"), _COUNT),
    **dict.fromkeys(("core_clocks", "adders", "multipliers", "mult_bits"), _COUNT_NAN),
    **dict.fromkeys(("px_per_clock", "px_per_clock_parallel", "shade_seconds"), _SIZE),
    "px_per_clock_core": ("float", 0.0, math.inf, True),
    "sw_pixels_per_second": _SIZE,
}
"""Every figure of a result (``evaluate``): kind, legal range, NaN allowed (no specular unit, no
highlight pixel; a BRDF unit: no shading core, no LSB figures, a form whose arithmetic is not
counted).  A cached result is used only when every one is present and legal, so an entry
written before a figure was added (``core_clocks``, ``px_per_clock_core``) is named and evaluated
again, never mixed with the new ones."""


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
        if nan_ok and isinstance(x, float) and math.isnan(x):
            continue
        if isinstance(x, bool) or not isinstance(x, number):
            return f"{name} = {x!r} is not legal: legal is {legal}"
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
