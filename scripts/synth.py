# SPDX-License-Identifier: Apache-2.0
"""Synthesise, place and route the RTL units and the shading core on real FPGA parts and print the
figures (make synth).

Every run goes through ``model.hw.synthesise`` (a unit) or ``sim.synth_tops.synthesise`` (a top
of several files, the shading core, its parameters made above ``model.hw``): Yosys, then nextpnr
with a fixed seed (1, or the run's own in model.hw.parts.SEEDS); results cached in
out/synth/cache/; ``--jobs N`` runs N at a time (threads, each waiting on its tools).  With no
selection the default set runs: every unit and the core at its default configuration on every
part (the BRDF unit: each form), plus the specular unit's UP5K configuration on the UP5K
and the core's hybrid configuration on the ECP5-25F; every Fmax target is in it (docs/fpga.md,
"Synthesis").  Exit status 1 if a target is missed or a design that must fit
does not, 2 if a tool fails.

    python scripts/synth.py                                   # the default set
    python scripts/synth.py --units specular_unit --parts up5k --config up5k
    python scripts/synth.py --units brdf_unit --jobs 1        # both forms, every part
    python scripts/synth.py --units shading_core --parts ecp5-25f --config default hybrid
    python scripts/synth.py --jobs 2 --out out/synth --record docs/synth.json
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from model.hw import PARTS, UNITS, SynthError, SynthResult, default_runs, report, synthesise
from model.hw.parts import SEEDS
from model.hw.synth import every_part_configs
from sim import synth_tops

NAMES = [*UNITS, *synth_tops.TOPS]


def configs_of(name: str) -> list[str]:
    """The named configurations of a unit or a top."""
    return list(UNITS[name][1]) if name in UNITS else list(synth_tops.configs(name))


def run(name: str, config: str, part: str, seed: int) -> SynthResult:
    """One run of a unit or a top."""
    if name in UNITS:
        return synthesise(name, config, part, seed=seed)
    return synth_tops.synthesise(name, config, part, seed=seed)


def _names(values: list[str] | None) -> list[str] | None:
    if not values:
        return None
    return [v for value in values for v in value.replace(",", " ").split()]


def runs_of(args: argparse.Namespace) -> list[tuple[str, str, str]]:
    units, parts, configs = _names(args.units), _names(args.parts), _names(args.config)
    if units is None and parts is None and configs is None:
        return default_runs(tuple(synth_tops.TOPS))
    for unit in units or ():
        if unit not in NAMES:
            raise ValueError(f"unit {unit!r} is unknown: known units are {', '.join(NAMES)}")
    for part in parts or ():
        if part not in PARTS:
            raise ValueError(f"part {part!r} is unknown: known parts are {', '.join(PARTS)}")
    units, parts = units or NAMES, parts or list(PARTS)
    known = {c for u in units for c in configs_of(u)}
    for config in configs or ():
        if config not in known:
            raise ValueError(
                f"config {config!r} is unknown for {', '.join(units)}: named configurations "
                f"are {', '.join(sorted(known))}"
            )
    # without --config: each unit's "default" (the BRDF unit: each form)
    chosen = {u: configs or every_part_configs(u) for u in units}
    return [(u, c, p) for u in units for c in chosen[u] if c in configs_of(u) for p in parts]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--units", nargs="*", help=f"units or tops (default all: {', '.join(NAMES)})"
    )
    parser.add_argument("--parts", nargs="*", help=f"parts (default all: {', '.join(PARTS)})")
    parser.add_argument(
        "--config",
        nargs="*",
        help="named configurations, e.g. default up5k hybrid (default: default)",
    )
    parser.add_argument(
        "--seed",
        type=int,
        help="nextpnr seed of every run (default: 1, or the run's own in model.hw.parts.SEEDS)",
    )
    parser.add_argument("--jobs", type=int, default=1, help="runs at a time (default 1)")
    parser.add_argument("--out", type=Path, help="write synth.md and synth.json into this folder")
    parser.add_argument("--record", type=Path, help="write the JSON record here (docs/synth.json)")
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error(f"--jobs {args.jobs} is not allowed: 1 or more")
    try:
        runs = runs_of(args)
    except ValueError as exc:
        parser.error(str(exc))
    start = time.monotonic()
    results, errors = [], []
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        seeds = [SEEDS.get(r, 1) if args.seed is None else args.seed for r in runs]
        futures = [pool.submit(run, *r, s) for r, s in zip(runs, seeds, strict=True)]
        for future in futures:
            try:
                results.append(future.result())
            except SynthError as exc:
                errors.append(str(exc))
    command = "python scripts/synth.py" + "".join(
        f" {a}" for a in map(shlex.quote, argv if argv is not None else sys.argv[1:])
    )
    table = report.table(results)
    print(table)
    print(f"{len(results)} runs in {time.monotonic() - start:.0f} s (cached runs are instant)")
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "synth.md").write_text(table)
        (args.out / "synth.json").write_text(report.dumps(results, command))
    if args.record:
        args.record.parent.mkdir(parents=True, exist_ok=True)
        args.record.write_text(report.dumps(results, command))
    bad = report.failures(results)
    for line in bad:
        print(f"FAILED: {line}", file=sys.stderr)
    for line in errors:
        print(f"error: {line}", file=sys.stderr)
    return 2 if errors else 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
