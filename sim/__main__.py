# SPDX-License-Identifier: Apache-2.0
"""Command line of the RTL side: ``python -m sim <command>``; ``<command> --help`` shows each
command's options and examples.

Commands:
  bench   pixels per second of the scene co-simulation: every span of a scene through the three
          RTL units under Icarus (``sim.scene_cosim``), the image compared with the model's byte
          for byte (``make bench`` runs it after ``python -m model bench``, the software speed)

Argument checks are this module's own (``sim`` sits below ``model.cli``): a bad value is refused
in one line naming the argument, its value and what is allowed, exit status 2, before any work.
"""

from __future__ import annotations

import argparse
import shutil
import sys

from model.render import meshfile, scene, scenefile

PROG = "python -m sim"


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
        "Pixels per second of the scene co-simulation: every span through the three RTL units "
        "under Icarus, the image compared with the model's byte for byte."
    )
    p = sub.add_parser(
        "bench",
        help=summary,
        description=summary,
        epilog="examples:\n"
        "  python -m sim bench                          # sphere, 64 x 64\n"
        "  python -m sim bench --scene torus --size 48\n"
        "  python -m sim bench --scene teapot --size 128 --config out/fit/teapot/config.toml",
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
        "co-simulation shades tens of pixels a second, its three Icarus builds included)",
    )
    p.add_argument(
        "--config",
        type=config_arg,
        default=None,
        metavar="FILE",
        help="the units at this pipeline configuration (a TOML file, e.g. the config.toml of a "
        "`shading fit` bundle) instead of method (c)",
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
    if shutil.which("iverilog") is None or shutil.which("vvp") is None:
        print(
            f"{PROG} bench: error: Icarus Verilog (iverilog, vvp) not found; "
            "`make bench` installs it",
            file=sys.stderr,
        )
        return 1
    name, target = source.label, source.scene(size, size)
    print(f"== python -m sim bench: {name}, {size} x {size}, three RTL units under Icarus ==")
    cosim = cosimulate(target, size, config or "hybrid", tag="scene_bench")
    same = bool(np.array_equal(cosim.rtl_rgb, cosim.model_rgb))
    for unit in cosim.jobs:
        print(
            f"  {unit}: {cosim.jobs[unit]} jobs, {cosim.results[unit]} results compared with the "
            f"model, {cosim.cycles[unit]} cycles, {cosim.seconds[unit]:.1f} s"
        )
    if not same:
        ys, xs = np.nonzero(np.any(cosim.rtl_rgb != cosim.model_rgb, axis=2))
        y, x = ys[0], xs[0]
        print(
            f"MISMATCH: {ys.size} pixels differ, first at x = {x}, y = {y}: RTL "
            f"{cosim.rtl_rgb[y, x].tolist()}, model {cosim.model_rgb[y, x].tolist()}"
        )
    print(
        f"co-simulation ({name} {size} x {size}): {cosim.pixels} pixels in "
        f"{sum(cosim.seconds.values()):.1f} s = {cosim.pixels_per_second:.0f} pixels/s "
        f"(builds included); image equal to the model's: {same}"
    )
    return 0 if same else 1


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    source = args.scene
    if args.mesh is not None:  # read after parsing, when --up is known, before any work
        try:
            source = scenefile.mesh_source(args.mesh, args.up)
        except ValueError as exc:
            args.command_parser.error(f"argument --mesh: {' '.join(str(exc).split())}")
    # one command today; the subcommand keeps room for more
    return bench(source, args.size, args.config)


if __name__ == "__main__":
    sys.exit(main())
