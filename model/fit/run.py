# SPDX-License-Identifier: Apache-2.0
"""``shading fit``: a scene and a target in, the fitted design's bundle out (docs/fit.md).

Owns ``fit`` (analyse, search, synthesise, write the bundle, check the model meets the target,
prove the fitted core's RTL on the scene), ``write_bundle`` and ``prove_rtl``; what it found is
a ``model.fit.report`` ``FitReport``.  The bundle, in ``out_dir``:

* ``config.toml``: the fitted pipeline configuration (``shading demo --config`` and
  ``model.render.configfile.read_config`` read it);
* ``shading_fit_top.v``, ``rtl/`` (the shading core's RTL, ``rtl/shading_core.f``'s files),
  ``rom/`` (the fitted ROM images) and ``shading_fit.f`` (the source list): the design, the core
  at its fitted parameters behind its range guard (``model.fit.verilog``); ``shading_fit.core``:
  its FuseSoC core;
* ``report.md``, ``fit.json``: what was chosen and why, the accuracy reached, the synthesised cost
  beside the default design's, the time taken; ``error.png``: the fitted image's error map.

May import ``model.fit``'s modules, ``model.render``, ``model.study``, ``model.hw`` and
``model.units``.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

from model.fit import analyse, cost, search, verilog
from model.fit.report import FitReport, report_text
from model.render import configfile, core, raster, scene, scenefile
from model.study import images

DEFAULT_PART = "ecp5-25f"
CACHE_DIR = Path("out/fit/cache")


def design_note(scene_name: str, size: int, target: str) -> str:
    """The comment the generated top level carries."""
    return f"Scene {scene_name} at {size} x {size}: {target}."


def write_bundle(report: FitReport, out_dir: Path, error_image) -> list[Path]:
    """The bundle's files (module docstring) into ``out_dir``."""
    cfg = report.result.config
    out_dir.mkdir(parents=True, exist_ok=True)
    written = [configfile.write_config(cfg, out_dir / "config.toml")]
    files = cost.design_files(cfg, design_note(report.scene, report.size, report.target.describe()))
    for name, data in files.items():
        path = out_dir / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
        written.append(path)
    rtl = [name for name in files if name.startswith("rtl/")]
    roms = sorted(name.removeprefix("rom/") for name in files if name.startswith("rom/"))
    core = out_dir / "shading_fit.core"
    core.write_text(verilog.fit_core(_core_name(report.scene), rtl, roms))
    written.append(core)
    written.append(images.save_error_heatmap(out_dir / "error.png", *error_image))
    (out_dir / "fit.json").write_text(json.dumps(report.record(), indent=1) + "\n")
    (out_dir / "report.md").write_text(report_text(report))
    return [*written, out_dir / "fit.json", out_dir / "report.md"]


def scene_arguments(source: scenefile.SceneSource) -> list[str]:
    """The command-line arguments naming ``source`` (``python -m sim bench`` takes them)."""
    if source.kind == "mesh":
        return ["--mesh", str(source.ref), "--up", source.up]
    return ["--scene", str(source.ref)]


def prove_rtl(source: scenefile.SceneSource, size: int, config: Path) -> dict:
    """Every span of the scene through the fitted shading core's RTL (``python -m sim bench
    --config --core-only``: ``sim.core_run.cosimulate`` at the fitted configuration, in a
    separate process, since ``sim`` sits beside ``model.study``, below nothing in ``model``);
    whether the frame equals the model's byte for byte in the clocks the model gives."""
    cmd = [sys.executable, "-m", "sim", "bench", *scene_arguments(source), "--size", str(size)]
    cmd += ["--config", str(config), "--core-only"]
    began = time.perf_counter()
    done = subprocess.run(cmd, capture_output=True, text=True)
    keep = [
        line.strip()
        for line in done.stdout.splitlines()
        if line.startswith(("== the shading core", "  scene", "FAIL"))
        or (line.startswith("  ") and line.rstrip().endswith(("equal", "DIFFERS")))
    ]
    if done.returncode not in (0, 1) or not keep:
        keep += [line for line in (done.stdout + done.stderr).splitlines()[-15:]]
    shown = " ".join(["python -m sim bench", *cmd[4:]])
    return {
        "equal": done.returncode == 0,
        "command": shown,
        "lines": keep,
        "seconds": round(time.perf_counter() - began, 1),
    }


def _core_name(name: str) -> str:
    return "".join(ch if ch.isalnum() else "_" for ch in name.lower()) or "scene"


def fit(
    source: scenefile.SceneSource | scene.Scene,
    size: int,
    out_dir: Path,
    target: search.Target | None = None,
    parts: tuple[str, ...] = (DEFAULT_PART,),
    *,
    lanes: int = 2,
    families: tuple[str, ...] = search.FAMILIES,
    synthesise: bool = True,
    compare_default: bool = True,
    rtl: bool = False,
    min_mhz: float | None = None,
    progress: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
    cache_dir: Path | None = CACHE_DIR,
    say=print,
) -> FitReport:
    """Fit the units to the scene (module docstring); ``say`` gets one line per stage.

    ``progress``: a progress bar of the search (tqdm, one tick per design tried).
    ``workers`` (>= 1) or ``scheduler`` (a Dask scheduler's address): the descents run on Dask
    (``model.fit.parallel``), as the trade study's sweep does; default: in this process."""
    target = target or search.Target()
    began = time.perf_counter()
    the_scene = source if isinstance(source, scene.Scene) else source.scene(size, size)
    name = the_scene.name if isinstance(source, scene.Scene) else source.key
    key = f"{name}-{size}-v{search.CACHE_VERSION}"
    frame_raster = raster.rasterise(the_scene)
    needs = analyse.analyse(frame_raster)
    for line in needs.summary():
        say(line)
    seconds = {"analyse": time.perf_counter() - began}
    t = time.perf_counter()
    cache = None if cache_dir is None else Path(cache_dir) / f"{_core_name(key)}.json"
    evaluate = search.Evaluator(frame_raster, key, cache)
    remote = 0
    if workers or scheduler:  # the descents on Dask, like the trade study's sweep
        from model.fit import parallel

        candidates, remote = parallel.search_candidates_dask(
            the_scene,
            evaluate,
            needs,
            target,
            lanes,
            workers=workers,
            scheduler=scheduler,
            families=families,
        )
    else:
        from tqdm import tqdm

        with tqdm(
            desc="search", unit=" designs", disable=not progress, leave=False, mininterval=0.5
        ) as bar:
            candidates = search.search_candidates(
                evaluate, needs, target, lanes, lambda: bar.update(), families
            )
    seconds["search"] = time.perf_counter() - t
    report = FitReport(the_scene.name, size, target, needs, candidates[0], min_mhz=min_mhz)
    if isinstance(source, scenefile.SceneSource):
        report.source = scene_arguments(source)
    report.renders, report.cache_hits = evaluate.renders + remote, evaluate.hits
    say(
        f"search: {'met' if candidates[0].met else 'NOT met'} {target.describe()}; "
        f"{len(candidates)} candidate designs ({evaluate.renders} renders, {evaluate.hits} cached)"
    )
    if synthesise:
        t = time.perf_counter()
        if candidates[0].met:  # the cheapest candidate on the first part, by synthesis
            for cand in candidates:
                fam = search.family(cand.config)
                say(f"synthesis of the {fam} {cand.policy} candidate on {parts[0]} ...")
                report.candidates.append((cand, cost.design_cost(cand.config, parts[0])))
            report.result = min(
                report.candidates,
                key=lambda c: (not report.fast_enough(c[1]), cost.part_share(c[1], parts[0])),
            )[0]
        result = report.result
        for part in parts:
            say(f"synthesis, place and route of the fitted design on {part} ...")
            report.costs[part] = cost.design_cost(result.config, part)
            if compare_default:
                say(f"... and of the default design on {part}")
                report.default_costs[part] = cost.default_cost(part)
        seconds["synthesis"] = time.perf_counter() - t
    result = report.result
    # The model proof: the fitted configuration, rendered afresh, meets the target.
    frame = evaluate.frame(result.config)
    check = search.metrics.compare(frame.rgb, evaluate.reference.rgb, highlight=evaluate.highlight)
    if result.met and not target.met(check):  # pragma: no cover - a defect, not an input error
        raise RuntimeError(f"fitted design misses the target on a fresh render: {check}")
    seconds["total"] = time.perf_counter() - began
    report.seconds = {k: round(v, 1) for k, v in seconds.items()}
    error_image = (frame.rgb, evaluate.reference.rgb, "fitted design")
    report.files = write_bundle(report, Path(out_dir), error_image)
    if rtl and isinstance(source, scenefile.SceneSource):
        say("the fitted core's RTL against the model, every span (python -m sim bench) ...")
        t = time.perf_counter()
        report.rtl_proof = prove_rtl(source, size, Path(out_dir) / "config.toml")
        # ... and no span beat of the scene trips the bundle's range guard (its model)
        words = core.frame_stream(frame_raster, result.config).words
        flagged = verilog.guard_flags(words, result.config)
        report.rtl_proof["guard"] = (
            f"range guard: {len(flagged)} of {len(words)} span beats flagged"
        )
        report.rtl_proof["lines"] += [report.rtl_proof["guard"], *flagged[:5]]
        report.rtl_proof["equal"] = report.rtl_proof["equal"] and not flagged
        seconds["rtl"] = time.perf_counter() - t
        seconds["total"] = time.perf_counter() - began
        report.seconds = {k: round(v, 1) for k, v in seconds.items()}
        report.files = write_bundle(report, Path(out_dir), error_image)
    return report
