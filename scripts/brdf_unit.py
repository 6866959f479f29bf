# SPDX-License-Identifier: Apache-2.0
"""Print the BRDF unit's data sheet tables (docs/brdf_unit.md, between its "hardware tables"
marks): ports, parameters with their legal ranges, timing and each form's cost; with
``--resources``, its "Resources" table instead (between the "resources" marks): each form's
synthesis figures per part beside the patent's specular unit, from the record ``make synth``
writes (docs/synth.json, or the record named).

python scripts/brdf_unit.py
python scripts/brdf_unit.py --resources [docs/synth.json]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from model.hw import report
from model.units.brdf import format_hardware

RECORD = Path(__file__).resolve().parent.parent / "docs" / "synth.json"
BASE = ("specular_unit", "default")
"""The row each form's figures are set against: the patent's specular unit, default widths."""
ALSO = (("specular_unit", "up5k"),)
"""The patent's configuration sized for the UP5K, shown on the parts the record has it on."""


def resources(record: Path = RECORD) -> str:
    """The "Resources" table of docs/brdf_unit.md from the synthesis record ``record``."""
    if not record.is_file():
        raise ValueError(f"record {str(record)!r} does not exist: pass a make synth record")
    return report.beside(report.load(record), "brdf_unit", BASE, ALSO)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--resources",
        nargs="?",
        const=RECORD,
        type=Path,
        metavar="RECORD",
        help=f"print the Resources table from a make synth record (default {RECORD.name})",
    )
    args = parser.parse_args(argv)
    if args.resources is None:
        print(format_hardware())
        return 0
    try:
        print(resources(args.resources), end="")
    except ValueError as exc:
        parser.error(str(exc))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
