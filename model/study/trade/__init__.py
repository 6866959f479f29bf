# SPDX-License-Identifier: Apache-2.0
"""The speed/accuracy trade study (``make trade``): every knob a config, swept over the scenes.

The package: ``points`` (trade points, the knobs, the grids, the scenes a point names),
``sweep`` (one point's figures, the result cache, the Dask engine), ``analysis`` (one row per
configuration, the Pareto fronts, where the default lies) and ``outputs`` (CSV, markdown, plots);
this module holds ``main`` (``python -m model trade``) and re-exports the names the tests and the
command line use.  May import ``model.render.meshes``, ``model.study.report`` and the package's own
modules.

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
``pareto_cycles.png`` and ``pareto_bits.png`` (the thesis's "visually identical" NMSE
threshold drawn as a labelled line; the front points and the default labelled, the labels
placed so that they do not collide: ``outputs.place_labels``).
"""

from __future__ import annotations

import functools
import time
from collections.abc import Sequence
from pathlib import Path

from model.render import scenefile as _scenefile
from model.study import report
from model.study.trade.analysis import (
    NEAR,
    aggregate,
    default_position,
    eps_dominates,
    front_objectives,
    near_front,
    pareto_mask,
)
from model.study.trade.outputs import (
    CSV_FIELDS,
    format_markdown,
    knob_summary,
    place_labels,
    plot_figure,
    plot_pareto,
    write_csv,
    write_outputs,
)
from model.study.trade.points import (
    CACHE_VERSION,
    DEFAULT_POINT,
    DEFAULT_SIZE,
    FILE_KEY,
    FULL_PRODUCT,
    GRIDS,
    K_SETS,
    KNOBS,
    NAMED,
    SMALL_SWEEPS,
    Sweep,
    TradePoint,
    a_int_bits_for,
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
    evaluate,
    load_cached,
    make_client,
    read_cached,
    run_sweep,
    store,
    sweep_lock,
)

__all__ = [
    "CACHE_VERSION",
    "CONNECT_TIMEOUT",
    "CSV_FIELDS",
    "DEFAULT_OUT",
    "DEFAULT_POINT",
    "DEFAULT_SIZE",
    "FILE_KEY",
    "FULL_PRODUCT",
    "GRIDS",
    "KNOBS",
    "K_SETS",
    "LOCK_NAME",
    "NAMED",
    "NEAR",
    "RESULT_RANGES",
    "SMALL_SWEEPS",
    "SetupError",
    "Sweep",
    "SweepOutcome",
    "TradePoint",
    "a_int_bits_for",
    "aggregate",
    "cache_path",
    "check_result",
    "check_sources",
    "check_workers",
    "connect",
    "default_position",
    "eps_dominates",
    "evaluate",
    "format_markdown",
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
    "store",
    "sweep_lock",
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
) -> int:
    """``python -m model trade``: sweep, cache, write the outputs, print the summary.

    ``scenes`` are built-in scenes' names or scene sources (a scene file, ``--scene``);
    ``meshes`` mesh files (``--mesh``) turned by ``up`` (``--up``), each one more scene
    (``check_sources``, ``point_scene``).  Before any work (``SetupError``, named after the
    command-line arguments): every file must load and frame, ``out_dir`` and ``figure_dir`` must
    be folders this user can create and write in, the sweep lock of ``out_dir/cache`` must be
    free (a second sweep on the same ``--out`` is refused, it does not wait) and ``scheduler``
    must answer within ``connect_timeout`` seconds."""
    workers = check_workers(workers, allow_zero=True)
    builtin = [
        s.ref if isinstance(s, _scenefile.SceneSource) else s
        for s in scenes
        if not isinstance(s, _scenefile.SceneSource) or s.kind == "builtin"
    ]  # each checked by TradePoint
    given = [s for s in scenes if isinstance(s, _scenefile.SceneSource) and s.kind != "builtin"]
    given += [_scenefile.SceneSource("mesh", str(m), up) for m in meshes or []]
    files = check_sources(given)
    scene_keys = list(dict.fromkeys([*builtin, *files]))
    points = grid_points(grid, scene_keys, size)
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
            )
        finally:
            if client is not None:
                client.close()


def _main(
    points, scenes, size, grid, out_dir, workers, client, figure_dir, repeats, evaluate_fn
) -> int:
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
        evaluate_fn=evaluate_fn,
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
