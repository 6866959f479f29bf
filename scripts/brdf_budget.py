# SPDX-License-Identifier: Apache-2.0
"""Print the BRDF family's fixed-point worst errors and the search for the most accurate unit
for n >= 8 at the patent's table budget: two markdown tables and the winner (docs/brdf.md).

First table: each thesis form's fixed-point unit (model.units.brdf.fixed) at its default
widths, against its own float form and against cos^n, exhaustively over every n = 1..1000 and
every angle register value in the epicentre.  Second: every candidate the budget search tried
(family, widths, table bits, float and fixed-point worst relative error over n = 8..1000 and
the float worst over n = 1..7), then the winner (model.units.brdf.budget).

python scripts/brdf_budget.py [--json PATH]

``--json PATH`` also writes the figures: the budget, per form its widths, table bits and worst
errors with their n and z, per candidate its row, and the winner.  It takes about two
minutes (most of it measuring every table k = 1..64 at 2^12 words exactly).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from model.units.brdf import (
    CONFIGS,
    budget_bits,
    candidates,
    fixed_accuracy,
    format_budget_table,
    format_fixed_table,
    table_bits,
    winner,
)


def figures() -> dict[str, object]:
    """The figures behind both tables (JSON-ready)."""
    forms = {}
    for name, cfg in CONFIGS.items():
        acc = fixed_accuracy(cfg)
        forms[name] = {
            "table_bits": table_bits(cfg),
            **{
                field: dict(zip(("value", "n", "z"), acc.worst(field, *span), strict=True))
                for field, span in (
                    ("abs_lsb", ()),
                    ("rel", ()),
                    ("rel_cos", (8,)),
                    ("float_rel", (8,)),
                )
            },
        }
    rows = [
        {
            "family": c.family,
            "widths": c.widths,
            "table_bits": c.bits,
            "float_worst": list(c.float_worst),
            "fixed_worst": list(c.fixed_worst),
            "small_n_float_worst": list(c.small_worst),
        }
        for c in candidates()
    ]
    best = winner()
    return {
        "budget_bits": budget_bits(),
        "forms": forms,
        "candidates": rows,
        "winner": {"family": best.family, "widths": best.widths, "table_bits": best.bits},
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", metavar="PATH", type=Path, help="also write the figures here")
    args = parser.parse_args(argv)
    print(format_fixed_table())
    print()
    print(format_budget_table())
    if args.json is not None:
        args.json.write_text(json.dumps(figures(), indent=1) + "\n")
        print(f"wrote {args.json}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
