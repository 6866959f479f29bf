# SPDX-License-Identifier: Apache-2.0
"""Command line: ``python -m model <command>`` (also installed as ``shading``); ``<command> --help``
shows each command's options and examples.

Commands:
  demo            the main job: a scene (built-in or a mesh file) through every method, images
                  in out/, the comparison table
  bench           pixels per second of the bit-exact pipeline against the float references (the
                  RTL co-simulation's speed is ``python -m sim bench``; ``make bench`` runs both)
  bench-load      seconds to load a 70k-triangle mesh file in each format (``make bench``)
  trade           the speed/accuracy trade study: every knob swept over the scenes on Dask,
                  cached and resumable; CSV, markdown and Pareto plots in out/trade/
  accuracy        every accuracy figure of the README, each a worst case (exhaustive or
                  proven), with the conditions it holds under, and the tables (markdown)
  roms            regenerate every ROM image under rtl/rom/ from the model
  divider-table   the article's Table 1, recomputed from the formula (markdown)
  divider-trade   worst error and cycles for N = 4..20 over k = 1..2047 (markdown)
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from model.render import meshfile, scenefile
from model.units import divider, specular

PROG = "shading"
SCENES = list(scenefile.SCENE_NAMES)


def accuracy_report() -> str:
    """``make accuracy``: the figures table, then the tables the README carries (the model's
    ``accuracy.figures`` computes everything; this only prints)."""
    from model.study import accuracy
    from model.units.brdf import claims as brdf_claims

    began = time.perf_counter()
    figs = accuracy.figures()
    parts = [
        "== Every accuracy figure: its worst case and where it holds ==",
        accuracy.format_figures(figs),
        "== Specular: the float approximation (exact maxima per n) ==",
        specular.format_brdf_table(),
        "== The thesis's BRDF family: exact worst epicentre errors beside its claims ==",
        brdf_claims.format_claims_table(),
        "== Specular: the fixed-point unit, default configuration ==",
        specular.format_accuracy_table(specular.DEFAULT, figs.specular["default"]),
        "== Specular: the fixed-point unit, UP5K configuration (fits an iCE40 UP5K) ==",
        specular.format_accuracy_table(specular.UP5K, figs.specular["up5k"]),
        "== Specular: per configuration ==",
        specular.format_config_table(figs.specular),
        "== Divider: worst error of 255/k and cycles, every k ==",
        accuracy.format_trade(),
        "== Divider: the article's Table 1 ==",
        accuracy.format_table1(),
        f"(computed in {time.perf_counter() - began:.1f} s)",
    ]
    return "\n\n".join(parts)


def write_roms() -> None:
    from model.units import brdf

    for path in divider.write_roms() + specular.write_roms() + brdf.write_roms():
        print(f"wrote {path}")


# ---------------------------------------------------------------------- scenes: a name or a file
def scene_notes(source: scenefile.SceneSource) -> list[str]:
    """What the command prints about where its scene came from: a mesh file's one-line summary
    (its repairs and up axis)."""
    return [source.read().summary()] if source.kind == "mesh" else []


def demo(
    source: scenefile.SceneSource,
    size: int,
    out_dir: Path,
    log_error: bool = False,
    config: Path | None = None,
) -> int:
    """The main job: the scene (a built-in name, a scene file or a mesh file) through every
    method, images into ``out_dir``, the table; with ``config`` (a pipeline configuration file,
    ``shading fit`` writes one) also the units at that configuration, as the method "config"."""
    from model.render import configfile
    from model.study import report

    methods, configs = None, {}
    if config is not None:
        try:
            configs = {"config": configfile.read_config(config)}
        except ValueError as exc:
            raise report.SetupError(f"argument --config: {' '.join(str(exc).split())}", 2) from None
        methods = [*report.METHOD_LABELS, "config"]

    began = time.perf_counter()
    print(f"== {source.label}, {size} x {size}: every method against (a) exact Blinn ==")
    for line in scene_notes(source):
        print(line)
    run = report.run_methods(
        source.scene(size, size), methods=methods, progress=True, configs=configs
    )
    print(report.format_table(run))
    print("\n== What the scene requires of the hardware ==")
    print(report.requirements(run))
    written = report.write_images(run, out_dir, log_error=log_error)
    print(f"\nwrote {len(written)} images to {out_dir}/ (sheet: {written[-1].name})")
    print(f"demo took {time.perf_counter() - began:.1f} s")
    return 0


def bench(
    sources: list[scenefile.SceneSource], sizes: list[int], repeats: int, studies: bool = False
) -> int:
    """Speed of the bit-exact pipeline against the float shaders, in one run (``study.bench``)."""
    from model.study import bench as bench_study

    return bench_study.main(sources, sizes, repeats, studies)


# ---------------------------------------------------------------------- argument types
def int_in(lo: int, hi: int | None = None):
    """An argparse ``type``: an integer in lo..hi (or >= lo); a bad value is refused by argparse
    as ``argument --workers: -3 is not allowed: must be an integer >= 1`` (exit status 2)."""
    legal = f"an integer >= {lo}" if hi is None else f"an integer in {lo}..{hi}"

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not allowed: must be {legal}") from None
        if value < lo or (hi is not None and value > hi):
            raise argparse.ArgumentTypeError(f"{value} is not allowed: must be {legal}")
        return value

    return parse


def scene_arg(text: str) -> scenefile.SceneSource:
    """An argparse ``type``: a built-in scene's name or a scene file (``scenefile.scene_source``),
    read while the arguments are parsed; a bad one is refused as ``argument --scene: <file>:
    camera.fov_y = 500 is out of range: legal range is 1.0..170.0`` (exit status 2)."""
    try:
        return scenefile.scene_source(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(" ".join(str(exc).split())) from None


def check_mesh(parser: argparse.ArgumentParser, path: str, up: str) -> scenefile.SceneSource:
    """``--mesh FILE --up AXIS``, read and framed after parsing (the axis is known then), before
    any work; a bad file is refused by ``parser.error`` in one line (exit status 2)."""
    try:
        return scenefile.mesh_source(path, up)
    except ValueError as exc:
        parser.error(f"argument --mesh: {' '.join(str(exc).split())}")
        raise  # parser.error exits


# ---------------------------------------------------------------------- the parser
def _command(sub, name: str, summary: str, examples: str) -> argparse.ArgumentParser:
    p = sub.add_parser(
        name,
        help=summary,
        description=summary,
        epilog="examples:\n" + examples,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.set_defaults(command_parser=p)  # its errors read "shading <command>: error: ..."
    return p


def _up(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--up",
        choices=meshfile.UP_AXES,
        default="auto",
        help="the mesh file's up axis, turned to the renderer's +z (default: auto: the "
        "format's convention, else a flat base, else z)",
    )


def _scene_or_mesh(p: argparse.ArgumentParser) -> None:
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--scene",
        type=scene_arg,
        default=scenefile.SceneSource("builtin", "teapot"),
        metavar="NAME|FILE",
        help=f"a built-in scene ({', '.join(SCENES)}; default: teapot) or a .toml scene file",
    )
    where.add_argument(
        "--mesh",
        default=None,
        metavar="FILE",
        help="a mesh file instead (" + ", ".join(meshfile.MESH_FORMATS) + "), repaired, "
        "turned by --up, framed by the default camera, light and material",
    )
    _up(p)


def _size(p: argparse.ArgumentParser, default: int) -> None:
    p.add_argument(
        "--size",
        type=int_in(8, 4096),
        default=default,
        metavar="N",
        help=f"image width and height, 8..4096 (default: {default})",
    )


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Hardware shading units: the bit-exact models' command line "
        "(`shading <command> --help` for a command's options and examples).",
        epilog="examples:\n"
        "  shading demo                       # the teapot through every method, into out/\n"
        "  shading demo --mesh bunny.obj      # your own mesh instead\n"
        "  shading trade --scenes sphere --grid small --workers 2",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="command")

    p = _command(
        sub,
        "demo",
        "The main job: a scene through every method; images in --out, the comparison table.",
        "  shading demo\n"
        "  shading demo --scene sphere --size 128 --out out/sphere\n"
        "  shading demo --mesh bunny.obj --size 512",
    )
    _scene_or_mesh(p)
    _size(p, 256)
    p.add_argument(
        "--out",
        type=Path,
        default=Path("out"),
        metavar="DIR",
        help="where images go (default: out)",
    )
    p.add_argument(
        "--log-error",
        action="store_true",
        help="error heat-maps on a symmetric-log scale (linear to 1 level, then decades)",
    )
    p.add_argument(
        "--config",
        type=Path,
        default=None,
        metavar="FILE",
        help="also shade with the units at this pipeline configuration (a TOML file, e.g. the "
        "config.toml of a `shading fit` bundle), as the method 'config'",
    )

    p = _command(
        sub,
        "fit",
        "Fit the units to a scene: the cheapest design meeting an accuracy target, written as a "
        "bundle (configuration, Verilog, ROMs, FuseSoC core, report; docs/fit.md).",
        "  shading fit                                   # the teapot, NMSE <= 0.00025\n"
        "  shading fit --scene sphere --size 128 --nmse 0.0001 --part up5k\n"
        "  shading fit --mesh head.obj --max-error 16 --out out/fit/head",
    )
    _scene_or_mesh(p)
    _size(p, 256)
    from model.fit import command as fit_cmd

    fit_cmd.add_arguments(p)

    p = _command(
        sub,
        "bench",
        "Pixels per second of the bit-exact pipeline against the float references (ratios); "
        "the RTL co-simulation is `python -m sim bench`.",
        "  shading bench\n"
        "  shading bench --scenes sphere teapot --sizes 64 512 --repeats 3\n"
        "  shading bench --mesh bunny.obj",
    )
    _scene_or_mesh(p)
    p.add_argument("--size", type=int_in(8, 4096), default=None, metavar="N",
                   help="one image size instead of --sizes, 8..4096")  # fmt: skip
    p.add_argument("--scenes", nargs="+", choices=SCENES, default=SCENES, metavar="NAME",
                   help=f"built-in scenes (default: all: {', '.join(SCENES)})")  # fmt: skip
    p.add_argument("--sizes", nargs="+", type=int_in(8, 4096), default=[64, 512, 1024],
                   metavar="N", help="image sizes, 8..4096 (default: 64 512 1024)")  # fmt: skip
    p.set_defaults(scene=None)
    p.add_argument(
        "--repeats",
        type=int_in(1),
        default=5,
        metavar="N",
        help="timed runs per method, >= 1 (default: 5)",
    )
    p.add_argument(
        "--studies", action="store_true", help="also (g)'s gain against n, and the scaling plot"
    )

    p = _command(
        sub,
        "bench-load",
        "Seconds to load a mesh file of about 70k triangles in each format (OBJ, PLY, OFF, STL, "
        "GLB), repaired, turned and normalised as --mesh does; target under 2 s each.",
        "  shading bench-load\n  shading bench-load --triangles 200000 --repeats 1",
    )
    p.add_argument(
        "--triangles",
        type=int_in(100, 10_000_000),
        default=70_000,
        metavar="N",
        help="about how many triangles, 100..10000000 (default: 70000)",
    )
    p.add_argument(
        "--repeats",
        type=int_in(1),
        default=3,
        metavar="N",
        help="timed loads per format, >= 1 (default: 3)",
    )

    p = _command(
        sub,
        "trade",
        "The speed/accuracy trade: every knob swept over the scenes on Dask (cached, "
        "resumable); CSV, markdown and Pareto plots in --out.",
        "  shading trade\n"
        "  shading trade --scenes sphere torus --size 64 --workers 4\n"
        "  shading trade --mesh bunny.obj --scheduler tcp://10.0.0.5:8786 --config fit.toml",
    )
    p.add_argument(
        "--scenes",
        "--scene",
        nargs="+",
        type=scene_arg,
        default=None,
        metavar="NAME|FILE",
        help=f"built-in scenes ({', '.join(SCENES)}) or .toml scene files (default: every "
        "built-in scene, unless --mesh)",
    )
    p.add_argument(
        "--mesh",
        type=Path,
        action="append",
        default=[],
        metavar="FILE",
        dest="meshes",
        help="a mesh file to sweep too (repeatable; each checked before any work)",
    )
    _up(p)
    _size(p, 128)
    p.add_argument("--grid", choices=["small", "full"], default="small")
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--workers",
        type=int_in(1),
        default=None,
        metavar="N",
        help="local Dask worker processes, >= 1",
    )
    where.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="address of an existing Dask scheduler (must answer within 5 s)",
    )
    p.add_argument(
        "--out",
        type=Path,
        default=Path("out/trade"),
        metavar="DIR",
        help="where outputs go (default: out/trade)",
    )
    p.add_argument(
        "--figure", type=Path, default=None, metavar="DIR", help="also write trade_pareto.png here"
    )
    p.add_argument(
        "--part", nargs="+", default=["ecp5-25f"], metavar="PART",
        help="synthesise the sweep's units on these parts (up5k, hx8k, ecp5-25f, gw1nr-9, xc7; "
        "default ecp5-25f) for the LUT, FF, BRAM, DSP, Fmax, Mpx/s columns and one set of "
        "fronts per part (the first in --out, each other in --out/<part>/); none: skip",
    )  # fmt: skip
    p.add_argument(
        "--config", type=Path, action="append", default=[], metavar="FILE", dest="configs",
        help="a pipeline configuration file (e.g. out/fit/<scene>/config.toml) swept as one "
        "more point, marked on every plot (repeatable)",
    )  # fmt: skip

    _command(
        sub,
        "accuracy",
        "Every accuracy figure of the README as a worst case (exhaustive or proven), with the "
        "conditions it holds under, and the tables (markdown).",
        "  shading accuracy\n  shading accuracy > accuracy.md",
    )
    _command(
        sub,
        "roms",
        "Regenerate every ROM image under rtl/rom/ from the model.",
        "  shading roms\n  shading roms && git diff --stat rtl/rom/",
    )
    _command(
        sub,
        "divider-table",
        "The article's Table 1 (255/k, k = 2..16), recomputed from the formula (markdown).",
        "  shading divider-table\n  python -m model divider-table > table1.md",
    )
    _command(
        sub,
        "divider-trade",
        "Worst error of 255/k and cycles for N = 4..20 reciprocal bits over k = 1..2047 "
        "(markdown).",
        "  shading divider-trade\n  python -m model divider-trade > divider-trade.md",
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return _run(parser, args)
    except Exception as exc:
        from model.study.report import (
            SetupError,  # here: `divider-table` need not import the renderer
        )

        if not isinstance(exc, SetupError):
            raise
        # Found before any work (an unwritable --out, an unreachable --scheduler, a held lock):
        # one line, no traceback.
        print(f"{parser.prog} {args.command}: error: {exc}", file=sys.stderr)
        return exc.status


def _run(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    if args.command == "trade":
        from model.study import trade

        scenes = args.scenes if args.scenes is not None else ([] if args.meshes else SCENES)
        scenes = [s.ref if getattr(s, "kind", "") == "builtin" else s for s in scenes]
        for mesh in args.meshes:  # each read and framed before any work
            check_mesh(args.command_parser, str(mesh), args.up)
        return trade.main(
            scenes=scenes,
            size=args.size,
            grid=args.grid,
            out_dir=args.out,
            workers=args.workers,
            scheduler=args.scheduler,
            figure_dir=args.figure,
            meshes=args.meshes,
            up=args.up,
            part=args.part,
            configs=args.configs,
        )
    if args.command in ("demo", "bench"):
        source = args.scene
        if args.mesh is not None:
            source = check_mesh(args.command_parser, args.mesh, args.up)
        if args.command == "bench":  # --scene, --mesh, --size: one scene or size instead
            sources = [source] if source else [scenefile.scene_source(n) for n in args.scenes]
            sizes = [args.size] if args.size else args.sizes
            return bench(sources, sizes, args.repeats, args.studies)
        from model.study import report

        report.check_output_dir("--out", args.out)
        return demo(source, args.size, args.out, args.log_error, args.config)
    if args.command == "fit":
        from model.fit import command as fit_cmd

        source = args.scene
        if args.mesh is not None:
            source = check_mesh(args.command_parser, args.mesh, args.up)
        return fit_cmd.run_command(args, source, scene_notes(source))
    if args.command == "bench-load":
        from model.study import loading

        head = f"about {args.triangles:,} triangles a file, best of {args.repeats}"
        print(f"== bench-load: {head} ==")
        print(loading.format_load_bench(loading.load_bench(args.triangles, args.repeats)))
    elif args.command == "roms":
        write_roms()
    elif args.command == "divider-table":
        from model.study import accuracy

        print(accuracy.format_table1())
    elif args.command == "divider-trade":
        from model.study import accuracy

        print(accuracy.format_trade())
    elif args.command == "accuracy":
        print(accuracy_report())
    return 0


if __name__ == "__main__":
    sys.exit(main())
