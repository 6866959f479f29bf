"""Command line: ``python -m model <command>`` (also installed as ``shading``).

Commands:
  demo            the main job: a scene through every method, images in out/, the comparison
  bench           pixels per second of the bit-exact pipeline against the float references,
                  and of the RTL co-simulation
  roms            regenerate every ROM image under rtl/rom/ from the model
  divider-table   the article's Table 1, recomputed from the formula (markdown)
  divider-trade   worst error and cycles for N = 4..20 over k = 1..2047 (markdown)
  accuracy        every accuracy figure of the README, each a worst case (exhaustive or
                  proven), with the conditions it holds under, and the tables (markdown)
  trade           the speed/accuracy trade study: every knob swept over the scenes on Dask,
                  cached and resumable; CSV, markdown and Pareto plots in out/trade/
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from model.units import divider, specular
from model.units.fixed import format_up


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


def demo(scene_name: str, size: int, out_dir: Path) -> int:
    """The main job: the scene through every method, images into ``out_dir``, the table."""
    from model.study import report

    began = time.perf_counter()
    print(f"== {scene_name}, {size} x {size}: every method against (a) exact Blinn ==")
    run = report.run_methods(scene_name, size, progress=True)
    print(report.format_table(run))
    print("\n== What the scene requires of the hardware ==")
    print(report.requirements(run))
    written = report.write_images(run, out_dir)
    print(f"\nwrote {len(written)} images to {out_dir}/ (sheet: {written[-1].name})")
    print(f"demo took {time.perf_counter() - began:.1f} s")
    return 0


def bench(scene_name: str, size: int, repeats: int) -> int:
    """Speed of the bit-exact pipeline against the float references, in one run, as ratios."""
    from model.study import report

    run = report.run_methods(
        scene_name, size, methods=["exact", "phong", "hybrid", "adaptive"], repeats=repeats
    )
    pps = {name: r.pixels_per_second for name, r in run.results.items()}
    print(f"== make bench: {scene_name} {size} x {size}, best of {repeats} (shading only) ==")
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
    try:
        from sim.scene_cosim import cosimulate
    except ImportError as exc:  # the dev extra (cocotb) is not installed
        print(f"co-simulation not run: {exc}; `make bench` installs it")
        return 1
    cosim = cosimulate("sphere", 64, tag="scene_bench")
    same = bool(np.array_equal(cosim.rtl_rgb, cosim.model_rgb))
    print(
        f"co-simulation (sphere 64 x 64, three RTL units under Icarus): {cosim.pixels} pixels in "
        f"{sum(cosim.seconds.values()):.1f} s = {cosim.pixels_per_second:.0f} pixels/s "
        f"(builds included); image equal to the model's: {same}"
    )
    return 0 if same else 1


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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="shading", description=__doc__.split("\n")[0])
    parser.add_argument(
        "command",
        choices=["demo", "bench", "roms", "divider-table", "divider-trade", "trade", "accuracy"],
    )
    scenes = ["sphere", "torus", "teapot", "quad"]
    parser.add_argument("--scene", default="teapot", choices=scenes)
    parser.add_argument(
        "--size",
        type=int_in(8, 4096),
        default=None,
        help="image width and height, 8..4096 (256; trade: 128)",
    )
    parser.add_argument(
        "--out", type=Path, default=None, help="where outputs go (out; trade: out/trade)"
    )
    parser.add_argument(
        "--repeats", type=int_in(1), default=5, help="timed runs per method, >= 1 (bench)"
    )
    trade = parser.add_argument_group("trade")
    trade.add_argument("--scenes", nargs="+", choices=scenes, default=scenes)
    trade.add_argument("--grid", choices=["small", "full"], default="small")
    where = trade.add_mutually_exclusive_group()
    where.add_argument(
        "--workers", type=int_in(1), default=None, help="local Dask worker processes, >= 1"
    )
    where.add_argument(
        "--scheduler",
        default=None,
        help="address of an existing Dask scheduler (must answer within 5 s)",
    )
    trade.add_argument("--figure", type=Path, default=None, help="also write trade_pareto.png here")
    args = parser.parse_args(argv)
    is_trade = args.command == "trade"
    if args.size is None:
        args.size = 128 if is_trade else 256
    if args.out is None:
        args.out = Path("out/trade") if is_trade else Path("out")
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

        return trade.main(
            args.scenes, args.size, args.grid, args.out, args.workers, args.scheduler, args.figure
        )
    if args.command == "demo":
        from model.study import report

        report.check_output_dir("--out", args.out)
        return demo(args.scene, args.size, args.out)
    if args.command == "bench":
        return bench(args.scene, args.size, args.repeats)
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
