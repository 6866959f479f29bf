# SPDX-License-Identifier: Apache-2.0
"""``shading fit`` on the command line: its options and what it prints (``model.cli`` parses
the scene and the size, then calls ``run_command``).  May import ``model.fit``, ``model.hw``,
``model.render``, ``model.study`` and ``model.units``."""

from __future__ import annotations

import argparse
from pathlib import Path

from model.hw.parts import PARTS
from model.render import scenefile
from model.units import brdf


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The options of ``shading fit`` besides the scene and the size."""
    p.add_argument(
        "--nmse",
        type=positive,
        default=0.00025,
        metavar="X",
        help="NMSE target (default: 0.00025, the thesis's 'visually identical')",
    )
    p.add_argument(
        "--max-error",
        type=positive,
        default=None,
        metavar="LEVELS",
        help="also: largest error in 8-bit levels (> 0, at most 255)",
    )
    p.add_argument("--psnr", type=positive, default=None, metavar="DB", help="also: PSNR in dB")
    p.add_argument(
        "--min-fmax",
        type=positive,
        default=None,
        metavar="MHZ",
        help="keep only a design reaching this Fmax on the first --part",
    )
    p.add_argument(
        "--part",
        action="append",
        choices=[k for k in PARTS if k != "xc7"],
        default=None,
        help="the part(s) to synthesise for (repeatable; default: ecp5-25f)",
    )
    p.add_argument(
        "--family",
        action="append",
        default=None,
        metavar="NAME",
        help="a family of the highlight's unit the search may use (repeatable; default: every "
        "one): cos^k (the patent's specular unit) or a BRDF form with RTL ("
        + ", ".join(brdf.RTL_FORMS)
        + ")",
    )
    p.add_argument(
        "--lanes",
        type=int,
        choices=(2, 4, 8, 16),
        default=2,
        help="Gouraud lanes P: pixels per clock (default: 2, the cheapest)",
    )
    p.add_argument(
        "--out",
        type=Path,
        default=None,
        metavar="DIR",
        help="the bundle's folder (default: out/fit/<scene>)",
    )
    p.add_argument(
        "--workers",
        type=int_at_least_1,
        default=None,
        metavar="N",
        help="run the search's descents on a local Dask cluster of N processes (default: in "
        "this process)",
    )
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDR",
        help="run the descents on the Dask scheduler at ADDR (tcp://host:8786), as `trade` does",
    )
    p.add_argument(
        "--no-rtl",
        action="store_true",
        help="skip the proof that the fitted RTL's image equals the model's (Icarus)",
    )
    p.add_argument(
        "--no-synth", action="store_true", help="skip synthesis (the bundle has no cost table)"
    )


def int_at_least_1(text: str) -> int:
    """An argparse ``type``: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not allowed: must be an integer >= 1"
        ) from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} is not allowed: must be an integer >= 1")
    return value


def positive(text: str) -> float:
    """An argparse ``type``: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not allowed: must be a number > 0") from None
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"{text} is not allowed: must be a number > 0")
    return value


def run_command(args: argparse.Namespace, source: scenefile.SceneSource, notes: list[str]) -> int:
    """``shading fit``: prints the stages and the report; exit 0 when the target is met, 1 when
    it cannot be (the bundle then holds the closest design).  The fit's modules are imported
    here, not at the top: every ``shading`` command builds this parser."""
    from model.fit import run, search
    from model.study import report

    if args.min_fmax is not None and args.no_synth:
        args.command_parser.error(
            f"argument --min-fmax: {args.min_fmax:g} is not allowed with --no-synth: an Fmax "
            "comes from synthesis"
        )
    try:
        target = search.Target(args.nmse, args.max_error, args.psnr)
        families = tuple(search.check_family(f) for f in args.family or search.FAMILIES)
    except ValueError as exc:
        args.command_parser.error(str(exc))
    out = args.out or Path("out/fit") / Path(source.ref).stem
    report.check_output_dir("--out", out)
    print(f"== fit: {source.label}, {args.size} x {args.size}, {target.describe()} ==")
    for line in notes:
        print(line)
    found = run.fit(
        source,
        args.size,
        out,
        target,
        tuple(args.part or [run.DEFAULT_PART]),
        lanes=args.lanes,
        families=families,
        synthesise=not args.no_synth,
        rtl=not args.no_rtl,
        min_mhz=args.min_fmax,
        progress=True,
        workers=args.workers,
        scheduler=args.scheduler,
    )
    print()
    print((out / "report.md").read_text())
    print(f"wrote the bundle to {out}/ ({len(found.files)} files)")
    proved = not found.rtl_proof or found.rtl_proof["equal"]
    return 0 if found.result.met and proved and found.fmax_met else 1
