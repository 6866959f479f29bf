# SPDX-License-Identifier: Apache-2.0
"""Formal proofs of the RTL units with SymbiYosys and Yosys; prints the table (make formal).

Every job goes through ``model.hw.formal`` (docs/formal.md): the protocol properties proven by
k-induction, the quotient, every cover reached, every property failing on a deliberately broken
copy of the RTL (model.hw.mutants; the divider's div_zero_leak is the defect its released
version shipped), and the synthesised netlist proven equal to the RTL; the same
for the segment Gouraud unit (--units gouraud_segment, model.hw.formal_gouraud), and the
specular unit's protocol proof, covers and deliberate errors, its intensities proven equal to a
reference formula and its netlist equivalence at a reduced configuration (--units
specular_unit, model.hw.formal_specular), the BRDF unit's protocol proof of both forms, its
covers and deliberate errors (--units brdf_unit, model.hw.formal_brdf), and the shading
core's stream protocol (--units shading_core, model.hw.formal_core: the AXI4-Stream rules of
both ports, l + 1 pixel beats per span beat with tlast on the last, no deadlock, no beat after
reset).  The table is printed and written with every result to ``<out>/formal.json``.  Exit
status 1 if a job does not give the outcome it requires, 2 on bad arguments or a missing tool.

    python scripts/formal.py                    # everything (make formal)
    python scripts/formal.py --quick            # the subset make test runs
    python scripts/formal.py --units divider_shift --jobs 2 --out out/formal
    python scripts/formal.py --units gouraud_segment specular_unit
"""

from __future__ import annotations

import argparse
import json
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from model.hw import formal

ROOT = Path(__file__).resolve().parent.parent
UNITS = ("divider_shift", "gouraud_segment", "specular_unit", "brdf_unit", "shading_core")


def parse(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--units",
        nargs="*",
        default=list(UNITS),
        help=f"units (default: {' '.join(UNITS)})",
    )
    parser.add_argument("--jobs", type=int, default=1, help="jobs at a time (default 1)")
    parser.add_argument("--quick", action="store_true", help="the quick subset (make test)")
    parser.add_argument("--out", type=Path, default=ROOT / "out" / "formal", help="output folder")
    args = parser.parse_args(argv)
    units = [u for value in args.units for u in value.replace(",", " ").split()]
    if not units:
        parser.error("--units: name at least one unit")
    for unit in units:
        if unit not in UNITS:
            parser.error(f"--units: {unit!r} is unknown: the units are {', '.join(UNITS)}")
    if not 1 <= args.jobs <= 16:
        parser.error(f"--jobs: {args.jobs} is out of range: 1 to 16")
    args.units = units
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    try:
        formal.tool_env()
    except formal.FormalError as exc:
        print(f"formal: {exc}", file=sys.stderr)
        return 2
    todo = [j for u in args.units for j in formal.jobs(u, quick=args.quick)]
    print(f"formal: {len(todo)} jobs, {args.jobs} at a time, in {args.out}", flush=True)

    def one(job: formal.FormalJob) -> formal.FormalResult:
        result = formal.run_job(job, args.out)
        flag = "ok" if result.ok else "NOT OK"
        print(
            f"  {job.name}: {result.status}, {result.seconds:.1f} s ({flag}: {result.detail})",
            flush=True,
        )
        return result

    try:
        with ThreadPoolExecutor(max_workers=args.jobs) as pool:
            results = list(pool.map(one, todo))
    except formal.FormalError as exc:
        print(f"formal: {exc}", file=sys.stderr)
        return 2
    print()
    print(formal.table(results))
    record = formal.to_json(results)
    (args.out / "formal.json").write_text(json.dumps(record, indent=1))
    bad = [r.job.name for r in results if not r.ok]
    print(
        f"\n{len(results) - len(bad)} of {len(results)} jobs as required; "
        f"results in {args.out / 'formal.json'}"
    )
    if bad:
        print(f"NOT OK: {', '.join(bad)}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
