# SPDX-License-Identifier: Apache-2.0
"""The speed/accuracy trade study (``make trade``): every knob a config, swept over the scenes.

The package: ``points`` (trade points, the knobs, the grids, the scenes a point names, the points
of configuration files), ``sweep`` (one point's figures, the result cache, the Dask engine),
``hardware`` (the synthesised cost per configuration), ``analysis`` (one row per configuration,
the Pareto fronts, where the default lies), ``outputs`` (CSV, markdown, plots) and ``labels``
(plot labels that do not collide);
this module holds ``main`` (``python -m model trade``) and re-exports the names the tests and the
command line use.  May import ``model.render.meshes``, ``model.study.report`` and the package's own
modules.  ``sweep`` imports ``model.render.core`` (the shading core's clocks per frame).

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
| ``diffuse_mode`` | ``PipelineConfig.diffuse_mode`` (gouraud, unit, adaptive) | gouraud |
| ``brdf`` | ``PipelineConfig.brdf`` (the highlight's unit: ``BRDF_CHOICES``) | none |

``brdf`` is the BRDF family: "none", the patent's cos^k specular unit, or a form of
``brdf.unit.RTL_FORMS`` (read, never listed here: a form given RTL is a value at once), whose
default unit (``brdf.unit.UNIT_CONFIGS``) takes the highlight jobs with ``angle`` = the point's
specular configuration, so ``z_frac_bits`` reaches it; ``rom_addr_bits``, ``rom_data_bits``,
``k_set`` and ``alpha`` are the patent unit's tables and change nothing there (no grid varies them
with a BRDF unit: ``BRDF_KNOBS``).  A BRDF unit makes the highlight only: a point with
``specular_mode`` vertex or a ``diffuse_mode`` other than gouraud is refused (``ValueError``
naming the knobs) and no grid holds one; nor a form whose angle table is wider than
``z_frac_bits`` (``to_pipeline_config``).  The small grid has every form at the default other
knobs, the full grid each form x ``z_frac_bits`` 18/22/26 x ``recip_bits`` 14/20
(``FULL_BRDF_PRODUCT``).  Every family is on one set of fronts; each row names its ``family``
("cos^k" or the form), the plots mark it (one marker per family, a BRDF point's label starts
with its form) and results.md lists each front's points with their family.

``SpecularConfig.a_int_bits`` follows from the k-set and alpha: the narrowest integer part that
holds the largest a (3 bits for k = 16 tables, 5 for the prototype's cos^2: a up to 22.4).

**Scenes**: the built-in ones (``scenefile.SCENE_NAMES``), scene files (``--scene FILE.toml``)
and mesh files (``main(meshes=...)``, ``--mesh FILE``, turned by ``--up`` and framed by
``meshes.scene_from_mesh`` with its defaults), each evaluated like a built-in scene.  A file's
scene key is ``scene:<file name>@<12 hex>`` or ``mesh:<file name>@<12 hex>``
(``scenefile.SceneSource.key``: the sha1 of the file's bytes, and of the meshes a scene file
names, and of a mesh's up axis), so the cache follows the content; a file that cannot be read
and framed is refused before any work, in one line naming the file.

**Figures per point** (``evaluate``), against the exact float Blinn (a) of ``model.study.report``:
NMSE, PSNR, max error, highlight max error; the worst epicentre relative error of the unit's
ROM-12 path against cos^n over n = 1..1000 (``specular.fixed_point_accuracy``: where
cos^n >= 1/255; computed once per specular configuration, it does not depend on the scene); the
worst-case line drift of the divider + Gouraud increment over the longest line (levels; the
divider's figure that short scene spans cannot show); and cost.  With a BRDF unit
(``sweep.accuracy_figures``): the epicentre error is the unit's own worst, its output word F
against cos^n over n = 2..1000 and every angle register value of the epicentre
(``brdf.fixed_accuracy``'s ``rel_cos``, the same range and floor as the patent's figure); the
LSB figures (``epicentre_out_lsb``, ``unit_error_lsb``) are NaN (that analysis measures F before
x C, not the output at full-scale C); the angle drift is in angle-table address steps
(``cos_addr_bits``, a = 1).  Cost:

* ``cycles``: unit cycles per frame, the sum of the busy-plus-restart clocks of every job of every
  unit (``pipeline.unit_counters``; the diffuse jobs of ``diffuse_mode`` unit/adaptive, which
  run on the specular unit at n = 1, are ``diffuse_cycles``): the work, or the frame time of
  one unit of each kind in series.
* ``core_clocks``: the frame's clocks through the streaming shading core (``rtl/shading_core.v``,
  docs/core.md) built for the configuration: ``core.core_cycles(pixels_shaded, cfg)`` =
  ``core.latency(cfg)`` + pixels (18 with the patent's highlight path; with a BRDF form's pipe
  20 for the cosine-quadratic, 21 for the quadratic, 22 for the log2, 28 for the cubic), one
  pixel per clock with the span beats back to back and the output always ready.  These are the
  core model's clocks, which the core's RTL matches clock for clock (its stream bench's
  measured cycles equal them on every built-in scene and method, the BRDF methods among them:
  tests/test_core.py).  Beyond the latency the count does not depend on the knobs: the core
  makes one pixel per clock whatever P, N, the widths, the modes or the highlight's unit.
  ``px_per_clock_core`` = shaded pixels / ``core_clocks``: the throughput the study reports
  (the Pareto front's axis and the hardware's Mpx/s).  A configuration the core cannot build
  (a BRDF form without a pipe in it, ``core.CORE_FORMS``) has neither (NaN), is on no
  throughput front and has no ``hw_mpx_per_s``.  A BRDF point's ``frame_clocks`` (below, with
  the BRDF unit as the highlight unit) and ``cycles`` come from ``pipeline.unit_counters`` (its
  highlight jobs at the BRDF unit's own fill latency, ``brdf.cycles``).
* ``frame_clocks`` (the earlier estimate, kept as a column; ``trade.frame_clocks`` is also what
  ``model.study.adaptive`` counts): the units in parallel on a stream of spans, one divider and
  one Gouraud unit per colour channel (3 each) and one specular unit (white highlight, and the
  diffuse jobs), ``max(divider_cycles / 3, gouraud_cycles / 3, specular_cycles +
  diffuse_cycles)`` clocks (ideal buffering between them).
* ``px_per_clock`` = shaded pixels / ``cycles``; ``px_per_clock_parallel`` = shaded pixels /
  ``frame_clocks``.
* ``table_bits``: one copy of every ROM (``report.table_bits``: divider reciprocals, and ROM 9 +
  ROM 12 unless the specular unit is left out, or the BRDF unit's tables, ``brdf.table_bits``).
* ``adders``, ``multipliers``: the datapath arithmetic of the units in the parallel picture:
  3 dividers x 1 accumulating adder, 3 Gouraud units x ``gouraud.adder_counts(P)["total"]``
  (increment network, segment lanes, rounding bias), 1 specular unit x (1 accumulator adder, 2
  multipliers: x a and x C), no specular unit in "vertex" mode with the Gouraud diffuse term;
  or 1 BRDF unit x (``sweep.BRDF_ADDERS``, counted in rtl/brdf_<form>.v: 3 adders; its 3
  multipliers, ``brdf.multipliers``: the form's two and C x F; NaN for a form not counted yet).
  Rounding increments, comparators, saturation and the final sum-and-saturate are not counted.
  ``mult_bits``: the multipliers' partial-product bits (width x width), a proxy for their area.
* ``sw_pixels_per_second``: shaded pixels per second of the software model, best of ``repeats``
  timed runs after a warm-up (noisy: the workers share the machine).

**Engine** (``run_sweep``): Dask distributed futures, one per uncached point, collected with
``as_completed`` under a tqdm bar; a ``LocalCluster`` of worker processes by default, or an
existing cluster (``--scheduler ADDRESS``).  Every result is written at once, atomically, to
``<out>/cache/<key>.json``; a rerun evaluates only the keys not in the cache, so an interrupted
sweep resumes where it stopped.  A cache file that cannot be used (broken JSON, not an object, a
missing field, a figure out of ``RESULT_RANGES``: an entry written before ``core_clocks`` and
``px_per_clock_core`` existed lacks them) is evaluated again, and the run says so.  One
sweep at a time per cache: ``sweep_lock`` (``<out>/cache/sweep.lock``, ``fcntl.flock``) refuses a
second one at once with the pid of the first (it does not wait).  ``main`` checks the output
folders, the lock and the scheduler (``CONNECT_TIMEOUT``) before any work (``SetupError``).

**Synthesised cost** (``--part``, default ``hardware.DEFAULT_PART``; None/"none": skipped):
every distinct unit configuration the sweep uses through ``model.hw.synthesise`` on the same
Dask cluster (``hardware.run_synthesis``; a BRDF point's highlight unit is ``brdf_unit`` at its
``FixedConfig``, as ``make synth`` places it); per configuration LUT, FF, BRAM, DSP (the units'
sums), Fmax (the slowest synthesised unit's: still the units', not the shading core's own, which
is synthesised for its named configurations only, ``sim/synth_tops.py``) and ``hw_mpx_per_s`` =
``px_per_clock_core`` x Fmax (NaN where the core cannot be built).  Without synthesis the
throughput axis is ``px_per_clock_core``.

**Configuration files** (``--config FILE``, ``ConfigPoint``): one more configuration each,
labelled ``fit:<folder>`` or ``config:<stem>``, keyed by its content; a scene it refuses
(``ValueError``) is reported as refused, not failed.

**Outputs** (``write_outputs``): ``results.csv`` (one row per point), ``results.md`` (per config,
the mean/worst over the scenes, grouped by sweep, with its family, the Pareto marks, each
front's points with their families and what each knob buys),
``pareto_cycles.png``, ``pareto_bits.png``, ``pareto_lut.png`` (when synthesised) and
``pareto_throughput.png`` (the thesis's "visually identical" NMSE threshold drawn as a labelled
line; the front points, the default and the configuration files' points labelled, the labels
placed so that they do not collide: ``labels.place_labels``).

Size: about 510 lines, two thirds of them this docstring: the study's one description of its
knobs, figures and outputs, beside ``main``, which checks every argument before any work.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Sequence
from pathlib import Path

from model.render import configfile, pipeline
from model.render import scenefile as _scenefile
from model.study import report
from model.study.trade.analysis import (
    NEAR,
    aggregate,
    default_position,
    eps_dominates,
    front_families,
    front_objectives,
    near_front,
    pareto_mask,
)
from model.study.trade.hardware import (
    DEFAULT_PART,
    HW_FIELDS,
    PART_CHOICES,
    SynthOutcome,
    attach,
    check_part,
    run_synthesis,
    unit_configs,
)
from model.study.trade.outputs import (
    CSV_FIELDS,
    format_markdown,
    front_lines,
    knob_summary,
    place_labels,
    plot_figure,
    plot_pareto,
    write_csv,
    write_outputs,
)
from model.study.trade.points import (
    BRDF_CHOICES,
    BRDF_KNOBS,
    CACHE_VERSION,
    DEFAULT_POINT,
    DEFAULT_SIZE,
    FAMILIES,
    FILE_KEY,
    FULL_BRDF_PRODUCT,
    FULL_PRODUCT,
    GRIDS,
    K_SETS,
    KNOBS,
    NAMED,
    PATENT_FAMILY,
    SMALL_SWEEPS,
    ConfigPoint,
    Sweep,
    TradePoint,
    a_int_bits_for,
    config_from_dict,
    family,
    grid_configs,
    grid_points,
    point_scene,
    row_knobs,
)
from model.study.trade.sweep import (
    CONNECT_TIMEOUT,
    LOCK_NAME,
    RESULT_RANGES,
    SetupError,
    SweepOutcome,
    cache_path,
    check_result,
    check_workers,
    connect,
    core_clocks,
    evaluate,
    frame_clocks,
    load_cached,
    make_client,
    read_cached,
    run_sweep,
    store,
    sweep_lock,
)

__all__ = [
    "BRDF_CHOICES",
    "BRDF_KNOBS",
    "CACHE_VERSION",
    "CONNECT_TIMEOUT",
    "CSV_FIELDS",
    "DEFAULT_OUT",
    "DEFAULT_PART",
    "DEFAULT_POINT",
    "DEFAULT_SIZE",
    "FAMILIES",
    "FILE_KEY",
    "FULL_BRDF_PRODUCT",
    "FULL_PRODUCT",
    "GRIDS",
    "HW_FIELDS",
    "KNOBS",
    "K_SETS",
    "LOCK_NAME",
    "NAMED",
    "NEAR",
    "PART_CHOICES",
    "PATENT_FAMILY",
    "RESULT_RANGES",
    "SMALL_SWEEPS",
    "ConfigPoint",
    "SetupError",
    "Sweep",
    "SweepOutcome",
    "SynthOutcome",
    "TradePoint",
    "a_int_bits_for",
    "aggregate",
    "attach",
    "cache_path",
    "check_configs",
    "check_part",
    "check_result",
    "check_sources",
    "check_workers",
    "config_from_dict",
    "connect",
    "core_clocks",
    "default_position",
    "eps_dominates",
    "evaluate",
    "family",
    "format_markdown",
    "frame_clocks",
    "front_families",
    "front_lines",
    "front_objectives",
    "grid_configs",
    "grid_points",
    "knob_summary",
    "load_cached",
    "main",
    "make_client",
    "near_front",
    "pareto_mask",
    "place_labels",
    "plot_figure",
    "plot_pareto",
    "point_scene",
    "read_cached",
    "row_knobs",
    "run_sweep",
    "run_synthesis",
    "store",
    "sweep_lock",
    "unit_configs",
    "write_csv",
    "write_outputs",
]

DEFAULT_OUT = Path("out/trade")


def check_sources(sources: Sequence[_scenefile.SceneSource]) -> dict[str, _scenefile.SceneSource]:
    """The scene key of every scene file and mesh file (``SceneSource.key``) with its source, each
    read and framed once as the sweep will; or ``SetupError`` (status 2, before any work) naming
    the argument, the file and why it cannot be used."""
    files: dict[str, _scenefile.SceneSource] = {}
    for source in sources:
        arg = "--mesh" if source.kind == "mesh" else "--scene"
        try:
            key = source.key()
            point_scene(TradePoint(scene=key, size=8), {key: source})
        except OSError as exc:
            why = f"path = '{exc.filename}' cannot be read: {exc.strerror or exc}"
            raise SetupError(f"argument {arg}: {why}", status=2) from None
        except Exception as exc:  # trimesh and the scene checks: one line, whatever they said
            why = " ".join(str(exc).split())
            if source.ref not in why:
                why = f"path = '{source.ref}': {why}"
            raise SetupError(f"argument {arg}: {why}", status=2) from None
        files.setdefault(key, source)
    return files


def config_label(path: Path) -> str:
    """A configuration file's label on the plots: ``fit:<folder>`` for the ``config.toml`` of a
    ``shading fit`` bundle (``out/fit/teapot/config.toml``: ``fit:teapot``), else
    ``config:<file stem>``."""
    path = Path(path)
    if path.name == "config.toml" and path.parent.name:
        return f"fit:{path.parent.name}"
    return f"config:{path.stem}"


def check_configs(paths: Sequence[Path]) -> list[tuple[str, pipeline.PipelineConfig]]:
    """(label, configuration) of every ``--config`` file (``configfile.read_config``), labels
    made unique; or ``SetupError`` (status 2, before any work) in one line naming the file."""
    out: list[tuple[str, pipeline.PipelineConfig]] = []
    labels: set[str] = set()
    for path in paths:
        try:
            cfg = configfile.read_config(path)
        except ValueError as exc:
            raise SetupError(f"argument --config: {' '.join(str(exc).split())}", 2) from None
        label, n = config_label(path), 2
        while label in labels:
            label, n = f"{config_label(path)}#{n}", n + 1
        labels.add(label)
        out.append((label, cfg))
    return out


def _check_parts(part: str | Sequence[str] | None) -> list[str]:
    """The parts to synthesise on, in order, each checked (``check_part``): none for None or
    "none" (alone)."""
    parts = [part] if part is None or isinstance(part, str) else list(part)
    try:
        checked = [check_part(p) for p in parts]
    except ValueError as exc:
        raise SetupError(f"argument --part: {exc}", 2) from None
    if None in checked and len(parts) > 1:
        raise SetupError(
            f"argument --part: {' '.join(map(str, parts))} is not allowed: none skips synthesis "
            "and stands alone",
            2,
        )
    return list(dict.fromkeys(p for p in checked if p is not None))


# ================================================================================ the command
def main(
    scenes: Sequence[str | _scenefile.SceneSource] = _scenefile.SCENE_NAMES,
    size: int = DEFAULT_SIZE,
    grid: str = "small",
    out_dir: Path = DEFAULT_OUT,
    workers: int | None = None,
    scheduler: str | None = None,
    figure_dir: Path | None = None,
    repeats: int = 3,
    connect_timeout: float = CONNECT_TIMEOUT,
    *,
    meshes: list[Path] | None = None,
    up: str = "auto",
    part: str | Sequence[str] | None = DEFAULT_PART,
    configs: Sequence[Path] = (),
) -> int:
    """``python -m model trade``: sweep, cache, write the outputs, print the summary.

    ``scenes`` are built-in scenes' names or scene sources (a scene file, ``--scene``);
    ``meshes`` mesh files (``--mesh``) turned by ``up`` (``--up``), each one more scene
    (``check_sources``, ``point_scene``).  Before any work (``SetupError``, named after the
    command-line arguments): every file must load and frame, ``out_dir`` and ``figure_dir`` must
    be folders this user can create and write in, the sweep lock of ``out_dir/cache`` must be
    free (a second sweep on the same ``--out`` is refused, it does not wait) and ``scheduler``
    must answer within ``connect_timeout`` seconds.

    ``part`` (``--part``: a part or several; None or "none": no synthesis): the parts every unit
    configuration the sweep uses is synthesised on (``hardware.run_synthesis``, on the sweep's
    Dask cluster), giving the LUT, FF, BRAM, DSP, Fmax and hardware Mpx/s columns and one set
    of outputs and fronts per part: the first part's in ``out_dir`` (and ``figure_dir``), each
    other's in ``out_dir / part``.  ``configs`` (``--config``):
    pipeline configuration files, each one more configuration over the scenes
    (``ConfigPoint``); a scene such a configuration refuses (``ValueError``: a span too long,
    an n it does not keep) is reported, not a failure."""
    workers = check_workers(workers, allow_zero=True)
    parts = _check_parts(part)
    files_cfg = check_configs(configs)
    builtin = [
        s.ref if isinstance(s, _scenefile.SceneSource) else s
        for s in scenes
        if not isinstance(s, _scenefile.SceneSource) or s.kind == "builtin"
    ]  # each checked by TradePoint
    given = [s for s in scenes if isinstance(s, _scenefile.SceneSource) and s.kind != "builtin"]
    given += [_scenefile.SceneSource("mesh", str(m), up) for m in meshes or []]
    files = check_sources(given)
    scene_keys = list(dict.fromkeys([*builtin, *files]))
    points: list[TradePoint] = grid_points(grid, scene_keys, size)
    points += [
        ConfigPoint.from_config(label, cfg, s, size) for label, cfg in files_cfg for s in scene_keys
    ]
    out_dir = report.check_output_dir("--out", Path(out_dir))
    cache_dir = report.check_output_dir("--out", out_dir / "cache")
    if figure_dir is not None:
        report.check_output_dir("--figure", Path(figure_dir))
    evaluate_fn = functools.partial(evaluate, sources=files) if files else evaluate
    with sweep_lock(cache_dir):
        client = connect(scheduler, connect_timeout) if scheduler else None
        try:
            return _main(
                points,
                scene_keys,
                size,
                grid,
                out_dir,
                workers,
                client,
                figure_dir,
                repeats,
                evaluate_fn,
                parts,
            )
        finally:
            if client is not None:
                client.close()


def _main(
    points, scenes, size, grid, out_dir, workers, client, figure_dir, repeats, evaluate_fn, parts
) -> int:
    began = time.perf_counter()
    own = None
    if client is None and workers != 0:
        todo = any(load_cached(out_dir / "cache", p) is None for p in points)
        if todo or parts:  # one cluster for the points and the synthesis runs
            client = own = make_client(workers)
    try:
        return _sweep_and_report(
            points, scenes, size, grid, out_dir, workers, client, figure_dir, repeats,
            evaluate_fn, parts, began,
        )  # fmt: skip
    finally:
        if own is not None:
            cluster = own.cluster
            own.close()
            if cluster is not None:
                cluster.close()


def _sweep_and_report(
    points, scenes, size, grid, out_dir, workers, client, figure_dir, repeats, evaluate_fn, parts,
    began,
) -> int:  # fmt: skip
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
        evaluate_fn=evaluate_fn,
        lock=False,  # main holds it
    )
    by_key = {p.key: p for p in points}
    refused = {
        k: f"{by_key[k].label} on {by_key[k].scene}: {err.split(': ', 1)[-1]}"
        for k, err in outcome.failed.items()
        if isinstance(by_key.get(k), ConfigPoint) and "ValueError(" in err
    }
    failed = {k: e for k, e in outcome.failed.items() if k not in refused}
    results = outcome.results
    synth_failed: dict[str, str] = {}
    per_part: list[tuple[str | None, list[dict]]] = [(None, results)]
    if parts and results:
        cfgs = {p.config_key: p.to_pipeline_config() for p in points}
        wanted = {k: cfgs[k] for k in dict.fromkeys(r["config_key"] for r in results)}
        per_part = []
        for part in parts:
            print(f"trade: synthesising the units of {len(wanted)} configurations on {part}")
            synth = run_synthesis(wanted, part, client=client)
            per_part.append((part, attach(results, synth.figures, part)))
            synth_failed.update({f"{unit} on {part}": e for unit, e in synth.failed.items()})
            print(f"trade: {synth.jobs} unit configurations synthesised in {synth.seconds:.1f} s")
    written = []
    for i, (part, part_results) in enumerate(per_part):
        folder, figure = (out_dir, figure_dir) if i == 0 else (out_dir / str(part), None)
        part_rows, part_written = write_outputs(
            part_results, folder, figure, refused=list(refused.values())
        )
        written += part_written
        if i == 0:
            rows = part_rows
        else:
            print(f"\n== The fronts across families on {part} ({folder / 'results.md'}) ==")
            print("\n".join(front_lines(part_rows)))
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
        f"{len(failed)} failed, {len(refused)} refused by their configuration file; took "
        f"{time.perf_counter() - began:.1f} s"
    )
    for why in refused.values():
        print(f"REFUSED {why}")
    for key, err in failed.items():
        print(f"FAILED {key}: {err}")
    for unit, err in synth_failed.items():
        print(f"SYNTHESIS FAILED {unit}: {err}")
    return 1 if failed or synth_failed else 0
