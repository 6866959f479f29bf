"""Command line: ``python -m model <command>`` (also installed as ``shading``); ``<command> --help``
shows each command's options and examples.

Commands:
  demo            the main job: a scene (built-in or a mesh file) through every method, images
                  in out/, the comparison table
  bench           pixels per second of the bit-exact pipeline against the float references (the
                  RTL co-simulation's speed is ``python -m sim bench``; ``make bench`` runs both)
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
import functools
import math
import sys
import time
from pathlib import Path

from model.render import meshes, scene
from model.units import divider, specular
from model.units.fixed import format_up

PROG = "shading"
SCENES = list(meshes.SCENE_NAMES)


def divider_table1(recip_bits: int = 8, dividend: int = 255) -> list[dict]:
    """Table 1 of the article, recomputed: terms, error and relative error for k = 2..16."""
    cfg = divider.DividerConfig(a_width=9, k_width=5, recip_bits=recip_bits)
    rows = []
    for k in range(2, 17):
        approx = divider.divide(dividend, k, cfg) / 2.0**recip_bits
        exact = dividend / k
        rows.append(
            {
                "k": k,
                "terms": "+".join(f"1/{2**j}" for j in divider.reciprocal_terms(k, recip_bits)),
                "error": approx - exact,
                "relative_pct": 100.0 * (approx - exact) / exact,
            }
        )
    return rows


def format_table1() -> str:
    rows = divider_table1()
    lines = ["| k | terms | error | relative % |", "|---|---|---|---|"]
    lines += [
        f"| {r['k']} | {r['terms']} | {r['error']:+.4f} | {r['relative_pct']:+.2f} |" for r in rows
    ]
    worst = max(rows, key=lambda r: abs(r["error"]))
    mean_rel = sum(abs(r["relative_pct"]) for r in rows) / len(rows)
    lines.append("")
    lines.append(  # the largest rounded up (a bound), like every worst case (accuracy.format_up)
        f"max |error| {format_up(abs(worst['error']), 5)} at k = {worst['k']}; "
        f"mean |relative error| over k = 2..16: {format_up(mean_rel, 4)} %"
    )
    return "\n".join(lines)


def format_trade(k_max: int = 2047, bits: range = range(4, 21)) -> str:
    lines = [
        f"| N | worst abs error (255/k) | at k | worst rel error | at k | k with r = 0 "
        f"| cycles max | cycles mean | (k = 1..{k_max}) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for n in bits:
        r = divider.trade_row(n, k_max)
        lines.append(
            f"| {n} | {format_up(r.worst_abs_error, 4)} | {r.worst_abs_k} "
            f"| {format_up(r.worst_rel_error, 3, 100)} % "
            f"| {r.worst_rel_k} | {r.useless_k} | {r.cycles_max} | {r.cycles_mean:.2f} | |"
        )
    lines.append("")
    lines.append(
        f"exact restoring divider, default widths: {divider.cycles_exact()} cycles for every k"
    )
    return "\n".join(lines)


def accuracy_report() -> str:
    """``make accuracy``: the figures table, then the tables the README carries (the model's
    ``accuracy.figures`` computes everything; this only prints)."""
    from model.study import accuracy

    began = time.perf_counter()
    figs = accuracy.figures()
    parts = [
        "== Every accuracy figure: its worst case and where it holds ==",
        accuracy.format_figures(figs),
        "== Specular: the float approximation (exact maxima per n) ==",
        specular.format_brdf_table(),
        "== Specular: the fixed-point unit, default configuration ==",
        specular.format_accuracy_table(specular.DEFAULT, figs.specular["default"]),
        "== Specular: per configuration ==",
        specular.format_config_table(figs.specular),
        "== Divider: worst error of 255/k and cycles, every k ==",
        format_trade(),
        "== Divider: the article's Table 1 ==",
        format_table1(),
        f"(computed in {time.perf_counter() - began:.1f} s)",
    ]
    return "\n\n".join(parts)


def write_roms() -> None:
    for path in divider.write_roms() + specular.write_roms():
        print(f"wrote {path}")


# ---------------------------------------------------------------------- scenes: a name or a mesh
@functools.lru_cache(maxsize=4)
def load_mesh(path: Path) -> scene.Mesh:
    """``meshes.load_mesh``, once per file: the argument check loads it, the command reuses it."""
    return meshes.load_mesh(path)


def scene_for(source: str | Path, size: int) -> scene.Scene:
    """A built-in scene by name, or a mesh file framed by ``meshes.scene_from_mesh`` (its default
    material, camera and light), ``size`` x ``size``."""
    if isinstance(source, Path):
        return meshes.scene_from_mesh(load_mesh(source), width=size, height=size)
    return meshes.builtin_scene(source, size, size)


def run_methods(source: str | Path, size: int, **kwargs):
    """``report.run_methods`` on a built-in scene or on a mesh file.

    ``report.run_methods`` takes a built-in scene's name; a mesh file's scene is shaded here with
    the same steps (one raster, every method, each compared with (a), best of ``repeats``)."""
    from tqdm import tqdm

    from model.render import raster, reference, shade
    from model.study import metrics, report

    if not isinstance(source, Path):
        return report.run_methods(source, size, **kwargs)
    methods = list(kwargs.get("methods") or report.METHOD_LABELS)
    repeats, progress = kwargs.get("repeats", 1), kwargs.get("progress", False)
    sc = scene_for(source, size)
    frame_raster = raster.rasterise(sc)
    ref = shade.shade(frame_raster, reference.exact_blinn)
    highlight = metrics.highlight_mask(ref.specular)
    results = {}
    for name in tqdm(methods, desc=f"{sc.name} {size}x{size}", disable=not progress):
        shader = report.shader_for(name)
        shade.shade(frame_raster, shader)  # warm-up: numba compiles on the first call
        best, frame = math.inf, None
        for _ in range(max(1, repeats)):
            frame = shade.shade(frame_raster, shader)
            best = min(best, frame.stats.shade_seconds)
        results[name] = report.MethodResult(
            name=name,
            label=report.METHOD_LABELS.get(name, name),
            frame=frame,
            comparison=metrics.compare(frame.rgb, ref.rgb, highlight=highlight),
            seconds=best,
            table_bits=report.table_bits(name),
        )
    return report.SceneRun(sc.name, frame_raster, ref, highlight, results)


def scene_label(source: str | Path) -> str:
    return f"mesh {source}" if isinstance(source, Path) else source


def demo(source: str | Path, size: int, out_dir: Path, log_error: bool = False) -> int:
    """The main job: the scene (a built-in name or a mesh file) through every method, images into
    ``out_dir``, the table."""
    from model.study import report

    began = time.perf_counter()
    print(f"== {scene_label(source)}, {size} x {size}: every method against (a) exact Blinn ==")
    run = run_methods(source, size, progress=True)
    print(report.format_table(run))
    print("\n== What the scene requires of the hardware ==")
    print(report.requirements(run))
    written = report.write_images(run, out_dir, log_error=log_error)
    print(f"\nwrote {len(written)} images to {out_dir}/ (sheet: {written[-1].name})")
    print(f"demo took {time.perf_counter() - began:.1f} s")
    return 0


def bench(source: str | Path, size: int, repeats: int) -> int:
    """Speed of the bit-exact pipeline against the float references, in one run, as ratios."""
    from model.study import report

    run = run_methods(
        source, size, methods=["exact", "phong", "hybrid", "adaptive"], repeats=repeats
    )
    pps = {name: r.pixels_per_second for name, r in run.results.items()}
    print(f"== bench: {scene_label(source)} {size} x {size}, best of {repeats} (shading only) ==")
    print("| method | pixels/s | vs (a) exact Blinn | vs (b) Phong |")
    print("|---|---|---|---|")
    for name, value in pps.items():
        print(
            f"| {report.METHOD_LABELS[name]} | {value:,.0f} | {value / pps['exact']:.2f}x "
            f"| {value / pps['phong']:.2f}x |"
        )
    target = pps["hybrid"] / pps["exact"]
    print(
        f"\ntarget: bit-exact pipeline >= 5x faster than (a): measured {target:.2f}x "
        f"({'met' if target >= 5 else 'not met'})"
    )
    print("the RTL co-simulation's speed: python -m sim bench (make bench runs both)")
    return 0


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


def mesh_file(text: str) -> Path:
    """An argparse ``type``: a mesh file ``meshes.load_mesh`` reads and ``meshes.scene_from_mesh``
    frames, checked (loaded) while the arguments are parsed, before any work; a bad one is refused
    as ``argument --mesh: path = 'x.obj' does not exist: legal value is an existing .obj/.ply
    file`` (exit status 2)."""
    path = Path(text)
    try:
        meshes.scene_from_mesh(load_mesh(path), width=8, height=8)
    except ValueError as exc:
        why = " ".join(str(exc).split())  # one line, whatever trimesh said
        if "legal" not in why:
            why += ": must be an .obj or .ply file holding a triangle mesh"
        raise argparse.ArgumentTypeError(why) from None
    return path


# ---------------------------------------------------------------------- the parser
def _command(sub, name: str, summary: str, examples: str) -> argparse.ArgumentParser:
    return sub.add_parser(
        name,
        help=summary,
        description=summary,
        epilog="examples:\n" + examples,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )


def _scene_or_mesh(p: argparse.ArgumentParser) -> None:
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--scene", default="teapot", choices=SCENES, help="a built-in scene (default: teapot)"
    )
    where.add_argument(
        "--mesh",
        type=mesh_file,
        default=None,
        metavar="FILE",
        help="an .obj or .ply mesh instead, framed by the default camera, light and material",
    )


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

    p = _command(
        sub,
        "bench",
        "Pixels per second of the bit-exact pipeline against the float references (ratios); "
        "the RTL co-simulation is `python -m sim bench`.",
        "  shading bench\n"
        "  shading bench --scene sphere --size 128 --repeats 3\n"
        "  shading bench --mesh bunny.obj",
    )
    _scene_or_mesh(p)
    _size(p, 256)
    p.add_argument(
        "--repeats",
        type=int_in(1),
        default=5,
        metavar="N",
        help="timed runs per method, >= 1 (default: 5)",
    )

    p = _command(
        sub,
        "trade",
        "The speed/accuracy trade: every knob swept over the scenes on Dask (cached, "
        "resumable); CSV, markdown and Pareto plots in --out.",
        "  shading trade\n"
        "  shading trade --scenes sphere torus --size 64 --workers 4\n"
        "  shading trade --mesh bunny.obj --mesh part.ply --scheduler tcp://10.0.0.5:8786",
    )
    p.add_argument(
        "--scenes",
        nargs="+",
        choices=SCENES,
        default=None,
        metavar="NAME",
        help=f"built-in scenes: {', '.join(SCENES)} (default: all of them, unless --mesh)",
    )
    p.add_argument(
        "--mesh",
        type=mesh_file,
        action="append",
        default=[],
        metavar="FILE",
        dest="meshes",
        help="an .obj or .ply mesh to sweep too (repeatable)",
    )
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
        return _run(args)
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


def _run(args: argparse.Namespace) -> int:
    if args.command == "trade":
        from model.study import trade

        scenes = args.scenes if args.scenes is not None else ([] if args.meshes else SCENES)
        return trade.main(
            scenes=scenes,
            size=args.size,
            grid=args.grid,
            out_dir=args.out,
            workers=args.workers,
            scheduler=args.scheduler,
            figure_dir=args.figure,
            meshes=args.meshes,
        )
    if args.command in ("demo", "bench"):
        source = args.mesh if args.mesh is not None else args.scene
        if args.command == "bench":
            return bench(source, args.size, args.repeats)
        from model.study import report

        report.check_output_dir("--out", args.out)
        return demo(source, args.size, args.out, args.log_error)
    if args.command == "roms":
        write_roms()
    elif args.command == "divider-table":
        print(format_table1())
    elif args.command == "divider-trade":
        print(format_trade())
    elif args.command == "accuracy":
        print(accuracy_report())
    return 0


if __name__ == "__main__":
    sys.exit(main())
