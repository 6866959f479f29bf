# SPDX-License-Identifier: Apache-2.0
"""Command line of the RTL side: ``python -m sim <command>``; ``<command> --help`` shows each
command's options and examples.

Commands:
  bench   pixels per second of the scene co-simulation: every span of a scene through the three
          RTL units' vector benches (``sim.scene_cosim``) under the simulator SIM names (unset:
          ``verilator --binary`` when on PATH, else Icarus), the image compared with the
          model's byte for byte, each step timed; then the vector mode: each unit's plain
          Verilog vector bench (sim/vectors/tb_<unit>.v, no Python in the loop) replaying a
          200k-cycle stimulus of the committed sets' generator (``vector_sets.write_stimulus``,
          in a temporary folder) under Icarus and ``verilator --binary``, build and run timed
          apart, results per wall and per CPU second per simulator, and the soak path's steps
          in cycles per second (``make bench`` runs it after ``python -m model bench``, the
          software speed)

          The shading core: the scene's span stream through the core's RTL
          (``sim.core_run``, the stream bench under the same simulator), the frame compared with
          the model's byte for byte, and its measured pixels per clock, with Mpx/s at the core's
          placed Fmax (docs/synth.json, ``make synth``), for methods (c) and (h) and the
          highlight through each BRDF form on the scene, and for every built-in scene and
          method (the BRDF methods among them) at the same size (``--no-core`` skips it)

Argument checks are this module's own (``sim`` sits below ``model.cli``): a bad value is refused
in one line naming the argument, its value and what is allowed, exit status 2, before any work.

Size: about 500 lines: one command line, its checks and the bench's report, whose steps are
each a call into the module that runs it.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

from model.render import meshfile, scene, scenefile

PROG = "python -m sim"
TEAPOT_TARGET_S = 60  # the target: the teapot at 256 x 256 end to end through the RTL
VECTOR_CYCLES = 200_000
MAX_VECTOR_CYCLES = 10_000_000
VECTOR_SIMS = ("icarus", "verilator")
# The target: the specular unit's vector bench under Verilator, results per second.
VECTOR_TARGET = ("specular_unit", "verilator", 1_000_000)
# The soak path's stimulus, prediction and vector file together, cycles per CPU second per unit,
# measured on runs of SOAK_CYCLES cycles (one segment of a long soak, sim/soak.py SEGMENT): the
# fastest of SOAK_REPEATS after one of the same size, as the Verilator replays are the fastest of
# three.  The process's first large run also pays the kernel's page faults for its fresh arrays
# (up to about 0.6 s of system time, once per process), printed beside it; the next runs still
# vary (system time, the file's writes) by up to three times.
SOAK_TARGET = 2_000_000
SOAK_CYCLES = 1_000_000
SOAK_REPEATS = 3


def size_type(text: str) -> int:
    """An argparse ``type``: an image side in 8..``scene.MAX_RESOLUTION``."""
    legal = f"an integer in 8..{scene.MAX_RESOLUTION}"
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not allowed: must be {legal}") from None
    if not 8 <= value <= scene.MAX_RESOLUTION:
        raise argparse.ArgumentTypeError(f"{value} is not allowed: must be {legal}")
    return value


def cycles_type(text: str) -> int:
    """An argparse ``type``: a vector stimulus length in 100..``MAX_VECTOR_CYCLES``."""
    legal = f"an integer in 100..{MAX_VECTOR_CYCLES}"
    try:
        value = int(text.replace("_", ""))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not allowed: must be {legal}") from None
    if not 100 <= value <= MAX_VECTOR_CYCLES:
        raise argparse.ArgumentTypeError(f"{value} is not allowed: must be {legal}")
    return value


def scene_arg(text: str) -> scenefile.SceneSource:
    """An argparse ``type``: a built-in scene's name or a .toml scene file, read while the
    arguments are parsed (``scenefile.scene_source``)."""
    try:
        return scenefile.scene_source(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(" ".join(str(exc).split())) from None


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="The RTL side's command line (`python -m sim <command> --help` for a "
        "command's options and examples).",
        epilog="examples:\n  python -m sim bench\n  python -m sim bench --mesh bunny.obj --size 32",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="command")
    summary = (
        "Pixels per second of the scene co-simulation: every span through the three RTL units' "
        "vector benches under SIM (icarus or verilator; unset: verilator when on PATH, else "
        "icarus), the image compared with the model's "
        "byte for byte; then the vector mode: each unit's plain Verilog vector bench replaying "
        "a generated stimulus under Icarus and verilator --binary, results per second."
    )
    p = sub.add_parser(
        "bench",
        help=summary,
        description=summary,
        epilog="examples:\n"
        "  python -m sim bench                          # sphere, 64 x 64, then vector mode\n"
        "  python -m sim bench --scene teapot --size 128 --config out/fit/teapot/config.toml "
        "--no-vectors\n"
        "  python -m sim bench --vectors-only --vector-cycles 1000000",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--scene",
        type=scene_arg,
        default=scenefile.SceneSource("builtin", "sphere"),
        metavar="NAME|FILE",
        help=f"a built-in scene ({', '.join(scenefile.SCENE_NAMES)}; default: sphere) or a "
        ".toml scene file",
    )
    where.add_argument(
        "--mesh",
        default=None,
        metavar="FILE",
        help="a mesh file instead, turned by --up, framed by the default camera, light and "
        "material",
    )
    p.set_defaults(command_parser=p)  # its errors read "python -m sim bench: error: ..."
    p.add_argument(
        "--up",
        choices=meshfile.UP_AXES,
        default="auto",
        help="the mesh file's up axis (default: auto)",
    )
    p.add_argument(
        "--size",
        type=size_type,
        default=64,
        metavar="N",
        help=f"image width and height, 8..{scene.MAX_RESOLUTION} (default: 64; the "
        "co-simulation shades hundreds to thousands of pixels a second)",
    )
    p.add_argument(
        "--config",
        type=config_arg,
        default=None,
        metavar="FILE",
        help="the units at this pipeline configuration (a TOML file, e.g. the config.toml of a "
        "`shading fit` bundle) instead of method (c)",
    )
    mode = p.add_mutually_exclusive_group()
    mode.add_argument(
        "--no-vectors",
        action="store_true",
        help="skip the vector mode (the plain Verilog vector benches under Icarus and Verilator)",
    )
    mode.add_argument(
        "--vectors-only",
        action="store_true",
        help="the vector mode only, no scene co-simulation",
    )
    p.add_argument(
        "--no-core",
        action="store_true",
        help="skip the shading core's runs (its stream bench over every built-in scene and method)",
    )
    p.add_argument(
        "--core-only",
        action="store_true",
        help="the shading core's runs only (with --config: the scene through the core at that "
        "configuration, as `shading fit` proves a fitted core), no units, no vector mode",
    )
    p.add_argument(
        "--vector-cycles",
        type=cycles_type,
        default=VECTOR_CYCLES,
        metavar="N",
        help=f"cycles of each unit's generated vector stimulus, 100..{MAX_VECTOR_CYCLES} "
        f"(default: {VECTOR_CYCLES})",
    )
    return parser


def config_arg(text: str):
    """An argparse ``type``: a pipeline configuration file, read while the arguments are parsed
    (``configfile.read_config``); a bad one is refused in one line, exit status 2."""
    from model.render import configfile

    try:
        return configfile.read_config(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(" ".join(str(exc).split())) from None


def scene_simulator(from_env) -> tuple[str, str]:
    """The scene co-simulation's simulator and why: SIM when set (``from_env``, e.g.
    ``sim.runner.simulator``, refuses a bad value), else Verilator when on PATH, else Icarus."""
    if os.environ.get("SIM", "").strip():
        return from_env(), "SIM chooses"
    if shutil.which("verilator"):
        return "verilator", "SIM unset and verilator on PATH; SIM=icarus chooses Icarus"
    return "icarus", "SIM unset and no verilator on PATH"


def bench(source: scenefile.SceneSource, size: int, config=None) -> int:
    """The scene through the RTL units and the model: speed, and whether the images are equal."""
    import numpy as np

    try:
        from sim.scene_cosim import cosimulate
    except ImportError as exc:  # the dev extra (cocotb) is not installed
        print(
            f"{PROG} bench: error: co-simulation not run: {exc}; `make bench` installs it",
            file=sys.stderr,
        )
        return 1
    from sim import runner, vector_run

    try:
        sim, why = scene_simulator(runner.simulator)
        tool = vector_run.tool_version(sim)
    except (ValueError, RuntimeError) as exc:
        print(f"{PROG} bench: error: {exc}", file=sys.stderr)
        return 1
    name, target = source.label, source.scene(size, size)
    print(
        f"== python -m sim bench: {name}, {size} x {size}, three RTL units in vector mode under "
        f"{sim} ({tool}; {why}), load average {_load()} =="
    )
    try:
        cosim = cosimulate(target, size, config or "hybrid", tag="scene_bench", sim=sim)
    except AssertionError as exc:
        print(f"FAIL: {exc}")
        return 1
    same = bool(np.array_equal(cosim.rtl_rgb, cosim.model_rgb))
    for unit in cosim.jobs:
        steps = ", ".join(f"{k} {v:.2f}" for k, v in cosim.steps[unit].items())
        cached = " (cached)" if cosim.cached[unit] else ""
        print(
            f"  {unit}: {cosim.jobs[unit]} jobs, {cosim.results[unit]} results compared with the "
            f"model, {cosim.cycles[unit]} cycles, {cosim.seconds[unit]:.1f} s: {steps} s{cached}"
        )
    if not same:
        ys, xs = np.nonzero(np.any(cosim.rtl_rgb != cosim.model_rgb, axis=2))
        y, x = ys[0], xs[0]
        print(
            f"MISMATCH: {ys.size} pixels differ, first at x = {x}, y = {y}: RTL "
            f"{cosim.rtl_rgb[y, x].tolist()}, model {cosim.model_rgb[y, x].tolist()}"
        )
    builds = "reused (cached)" if all(cosim.cached.values()) else "included"
    print(
        f"co-simulation ({name} {size} x {size}, {sim}): {cosim.pixels} pixels in "
        f"{cosim.wall_s:.1f} s end to end = {cosim.pixels_per_second:.0f} pixels/s (builds "
        f"{builds}; the specular unit beside the divider and Gouraud units); image equal to the "
        f"model's: {same}"
    )
    if source.kind == "builtin" and source.ref == "teapot" and size == 256 and config is None:
        took = cosim.wall_s
        met = "met" if same and took < TEAPOT_TARGET_S else "not met"
        print(
            f"target: the teapot at 256 x 256 through the RTL, byte-equal, in under "
            f"{TEAPOT_TARGET_S} s: {took:.1f} s under {sim}, builds {builds} ({met})"
        )
    return 0 if same else 1


CORE_PART = "ecp5-25f"
"""The part whose placed Fmax turns the core's pixels per clock into Mpx/s."""
CORE_TARGET_PX_PER_CLOCK = 0.9
CORE_CONFIG = {"diffuse": "default"}
"""The core configuration of docs/synth.json (sim/synth_tops.py) each method's Mpx/s takes
the Fmax of: "default" for (h), "brdf_<form>" for a BRDF method (where make synth places it),
"hybrid" for the rest."""


def core_fmax(config: str, part: str = CORE_PART) -> float | None:
    """The placed Fmax (MHz) of the shading core at ``config`` on ``part`` in docs/synth.json
    (``make synth``), None if it has not been placed."""
    import json

    path = Path(__file__).resolve().parents[1] / "docs" / "synth.json"
    if not path.is_file():
        return None
    for row in json.loads(path.read_text()).get("results", []):
        if (
            row.get("unit") == "shading_core"
            and row.get("config") == config
            and (row.get("part") == part)
        ):
            return row.get("fmax_mhz")
    return None


def core_bench(source: scenefile.SceneSource, size: int, sim: str, config=None) -> int:
    """The scene's span stream through the core's RTL for (c), (h) and each BRDF method (or
    ``config``), then every built-in scene and method at ``size``: frame equal, pixels per
    clock, Mpx/s."""
    from model.render import pipeline
    from sim import core_run

    print(f"== the shading core (rtl/shading_core.f) under {sim}, output always ready ==")
    first = ("hybrid", "diffuse", *pipeline.BRDF_METHODS)
    runs = [(source.label, source.scene(size, size), name) for name in first]
    if config is not None:
        runs = [(source.label, source.scene(size, size), config)]
    if config is None:
        runs += [
            (name, name, method)
            for name in scenefile.SCENE_NAMES
            for method in (*pipeline.METHODS, *pipeline.BRDF_METHODS)
            if (name, method) not in {(source.label, m) for m in first}
        ]
    status = 0
    print(f"  {'scene':<10} {'method':<16} {'pixels':>8} {'clocks':>8} {'model':>8} "
          f"{'px/clk':>7} {'Mpx/s':>7}  frame")  # fmt: skip
    for label, target, method in runs:
        try:
            r = core_run.cosimulate(target, size, method, sim=sim, tag="core_bench")
        except AssertionError as exc:
            print(f"FAIL: {label} {method}: {exc}")
            return 1
        mname = method if isinstance(method, str) else "config"
        # a configuration of its own has no placed Fmax in docs/synth.json (CORE_CONFIG)
        brdf = mname in pipeline.BRDF_METHODS
        fmax = core_fmax(f"brdf_{mname}" if brdf else CORE_CONFIG.get(mname, "hybrid"))
        fmax = None if mname == "config" else fmax
        mpx = f"{r.run.px_per_clock * fmax:7.1f}" if fmax else "     --"
        same = "equal" if r.equal and r.run.cycles == r.model_cycles else "DIFFERS"
        status |= 0 if same == "equal" else 1
        print(f"  {label:<10} {mname:<16} {r.run.pixels:>8} {r.run.cycles:>8} "
              f"{r.model_cycles:>8} {r.run.px_per_clock:>7.4f} {mpx}  {same}")  # fmt: skip
        if label == source.label and mname in ("hybrid", "diffuse"):
            met = "met" if r.run.px_per_clock >= CORE_TARGET_PX_PER_CLOCK else "not met"
            got = f"{r.run.px_per_clock:.4f}"
            print(f"  target: {label} {mname} at {size} x {size}, at least "
                  f"{CORE_TARGET_PX_PER_CLOCK} px/clk: {got} ({met})")  # fmt: skip
        if label == source.label and mname in ("hybrid", "diffuse") and fmax:
            host = core_run.setup_rate(target, size, method)
            need = host.needed_per_second(r.run.px_per_clock, fmax)
            short = need * host.setup_seconds / host.spans
            print(f"  host: {host.spans} span beats for {host.pixels} pixels; at {fmax:.1f} MHz "
                  f"the core takes {need / 1e6:.2f} M span beats/s; the model's set-up on one "
                  f"CPU core makes {host.spans / host.setup_seconds / 1e6:.3f} M/s "
                  f"(pipeline.build_jobs), {host.spans_per_second / 1e6:.3f} M/s packed "
                  f"(+ core.span_beats): {short:.0f}x short")  # fmt: skip
    print(f"  Mpx/s = px/clk x the placed Fmax on the {CORE_PART} of the default core (both "
          f"paths) for (h), of the BRDF form's core for a BRDF method and of the hybrid core "
          "(the highlight path) for the others (docs/synth.json; -- where make synth has not "
          "placed it)")  # fmt: skip
    return status


def _load() -> str:
    """The 1-, 5- and 15-minute load averages (other work on the machine), as text."""
    try:
        return " / ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


def _soak_rates(
    cycles: int, prep: dict[str, dict[str, float]], first: dict[str, float], rows: list
) -> None:
    """The soak path's steps (sim/soak.py run_soak, make test) in cycles per second, and the
    stimulus, prediction and file together against ``SOAK_TARGET``."""
    print(
        "soak path (sim/soak.py run_soak: stimulus, protocol-model prediction and file by the "
        "numba kernels of sim/soak_stimulus.py, soak_predict.py and soak_file.py, CPU seconds of "
        f"the fastest of {SOAK_REPEATS} {SOAK_CYCLES:,}-cycle runs after one of the same size; "
        "then the replay of the "
        f"{cycles:,}-cycle set), cycles per second of each step; all three: stimulus + prediction "
        "+ file; first run: all three in the process's first run of that size, its fresh "
        "arrays' page faults included:"
    )
    head = ["unit", "stimulus", "predict", "write", "all three", "first run"]
    sims = sorted({sim for _, sim, *_ in rows})
    head += [f"{sim} {kind}" for sim in sims for kind in ("wall", "cpu")]
    w = max(16, *(len(unit) for unit in prep))
    print(f"{head[0]:<{w}} " + " ".join(f"{h:>14}" for h in head[1:]))
    for unit, steps in prep.items():
        cells = [SOAK_CYCLES / max(steps[k], 1e-9) for k in ("stimulus", "predict", "write")]
        cells.append(SOAK_CYCLES / max(sum(steps.values()), 1e-9))
        cells.append(SOAK_CYCLES / max(first[unit], 1e-9))
        for sim in sims:
            run = next(r for u, s, _, _, r in rows if u == unit and s == sim)
            cells += [cycles / max(run.run_s, 1e-9), cycles / max(run.run_cpu_s, 1e-9)]
        print(f"{unit:<{w}} " + " ".join(f"{c:>14,.0f}" for c in cells))
    rates = {unit: SOAK_CYCLES / max(sum(steps.values()), 1e-9) for unit, steps in prep.items()}
    verdict = ", ".join(
        f"{unit} {rate:,.0f} ({'met' if rate >= SOAK_TARGET else 'NOT met'})"
        for unit, rate in rates.items()
    )
    print(f"target: stimulus + prediction + file >= {SOAK_TARGET:,} cycles/s per unit: {verdict}")


def vector_bench(cycles: int, sims: tuple[str, ...] = VECTOR_SIMS) -> int:
    """Vector mode: each unit's default configuration, a ``cycles``-cycle stimulus of the
    committed sets' generator (seed ``vector_sets.SEED``) replayed by its plain Verilog bench
    under each simulator, build and run timed apart; the table, and 1 if any replay failed."""
    from model.units import brdf, divider, gouraud, specular
    from sim import soak, vector_sets

    configs = {"divider_shift": divider.DEFAULT, "gouraud_segment": gouraud.DEFAULT}
    configs["specular_unit"] = specular.DEFAULT
    # the BRDF unit: each form at its default widths (its committed sets' configurations)
    configs.update({f"brdf_{form}": cfg for form, cfg in brdf.UNIT_CONFIGS.items()})
    found = [s for s in sims if shutil.which("iverilog" if s == "icarus" else s)]
    for s in sorted(set(sims) - set(found)):
        print(f"vector mode: {s} not found on PATH, left out (`make tools` installs it)")
    print(
        f"== vector mode: {cycles} cycles per unit (sim/vector_sets.py write_stimulus, seed "
        f"{vector_sets.SEED}), replayed by sim/vectors/tb_<unit>.v without Python: instances "
        f"RESET_ALL = 0 and 1, every output compared every cycle; load average {_load()} =="
    )
    rows, failed = [], []
    prep: dict[str, dict[str, float]] = {}
    first: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="sim_bench_vectors_") as tmp:
        for unit, cfg in configs.items():
            t0 = time.monotonic()
            folder = Path(tmp) / unit
            folder.mkdir()
            steps: dict[str, float] = {}
            stats = vector_sets.write_stimulus(cfg, cycles, vector_sets.SEED, folder, steps)
            # the soak path's rate: a run of SOAK_CYCLES after one of the same size (SOAK_TARGET)
            warm = soak.write_segment(cfg, SOAK_CYCLES, vector_sets.SEED, 0, folder / "soak.bin")
            first[unit] = sum(warm[2].values())
            runs = [
                soak.write_segment(cfg, SOAK_CYCLES, vector_sets.SEED, 0, folder / "soak.bin")[2]
                for _ in range(SOAK_REPEATS)
            ]
            prep[unit] = min(runs, key=lambda steps: sum(steps.values()))
            (folder / "soak.bin").unlink()
            print(f"  {unit}: stimulus, model prediction and file in {time.monotonic() - t0:.1f} s")
            for sim in found:
                # Verilator's runs take a fraction of a second: the fastest of three counts
                repeats = 3 if sim == "verilator" else 1
                run = vector_sets.replay(folder, sim, Path(tmp) / f"{unit}_{sim}", repeats=repeats)
                if run.passed:
                    build = Path(tmp) / f"load_{sim}"
                    run.load_s = vector_sets.load_time(folder, sim, build, repeats=repeats)
                else:
                    failed.append(f"{unit} under {sim}")
                    print(f"FAIL {unit} under {sim}: {run.mismatches} mismatches")
                    print(run.log[-3000:])
                rows.append((unit, sim, cycles, stats.results_compared, run))
    head = ("unit", "simulator", "cycles", "results", "build s", "run s", "cpu s")
    head += ("results/s", "per cpu s", "read s")
    w = max(16, *(len(unit) for unit, *_ in rows))
    print(f"{head[0]:<{w}} {head[1]:<10} " + " ".join(f"{h:>10}" for h in head[2:]))
    rates = {}
    for unit, sim, n, results, run in rows:
        rate = results / run.run_s if run.run_s > 0 else 0.0
        cpu_rate = results / run.run_cpu_s if run.run_cpu_s > 0 else 0.0
        rates[unit, sim] = (rate, cpu_rate)
        print(
            f"{unit:<{w}} {sim:<10} {n:>10} {results:>10} {run.build_s:>10.2f} "
            f"{run.run_s:>10.3f} {run.run_cpu_s:>10.3f} {rate:>10.0f} {cpu_rate:>10.0f} "
            f"{run.load_s:>10.3f}" + ("" if run.passed else "  FAILED")
        )
    print(
        "results: the results the model predicts (each compared in both instances); run s: the "
        "bench's whole run (wall), reading its vector file included; cpu s: the CPU seconds of "
        "that run's simulator process (less sensitive to other load than the wall time); "
        "results/s: results / run s; per cpu s: results / cpu s; read s: the wall time of a "
        "bench that only reads the same file; Verilator: fastest of 3 runs; "
        f"load average {_load()}"
    )
    _soak_rates(cycles, prep, first, rows)
    unit, sim, target = VECTOR_TARGET
    if (unit, sim) in rates:
        rate, cpu_rate = rates[unit, sim]
        verdict = ", ".join(
            f"{label} {value:,.0f} ({'met' if value >= target else 'NOT met'})"
            for label, value in (("per wall second", rate), ("per CPU second", cpu_rate))
        )
        print(f"target: {unit} under {sim} >= {target:,} results/s: {verdict}")
    if failed:
        print(f"vector mode FAILED: {', '.join(failed)}")
        return 1
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    source = args.scene
    if args.mesh is not None:  # read after parsing, when --up is known, before any work
        try:
            source = scenefile.mesh_source(args.mesh, args.up)
        except ValueError as exc:
            args.command_parser.error(f"argument --mesh: {' '.join(str(exc).split())}")
    if args.core_only and (args.vectors_only or args.no_core):
        args.command_parser.error(
            "argument --core-only: not allowed with --vectors-only or --no-core"
        )
    # one command today; the subcommand keeps room for more
    units = not (args.vectors_only or args.core_only)
    status = bench(source, args.size, args.config) if units else 0
    if not args.vectors_only and not args.no_core:
        from sim import runner

        sim, _ = scene_simulator(runner.simulator)
        status = max(status, core_bench(source, args.size, sim, args.config))
    if not args.no_vectors and not args.core_only:
        status = max(status, vector_bench(args.vector_cycles))
    return status


if __name__ == "__main__":
    sys.exit(main())
