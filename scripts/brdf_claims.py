# SPDX-License-Identifier: Apache-2.0
"""Print the thesis's BRDF family against its accuracy claims: a markdown table (docs/brdf.md).

Each row: the claim, the exact worst relative error over the epicentre for n = 1..1000 and over
the claim's own n, whether the claim holds and the n where it fails (model.units.brdf).

python scripts/brdf_claims.py [--json PATH]

``--json PATH`` also writes the figures: per claim its bound, n range, worst errors with their n,
the failing n and the exact worst error of every n = 1..1000.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import asdict
from pathlib import Path

from model.units.brdf import check_claims, format_claims_table


def figures() -> list[dict[str, object]]:
    """The figures behind the table, one record per claim (JSON-ready)."""
    records = []
    for check in check_claims():
        (w, wn), (r, rn) = check.worst, check.worst_in_range
        records.append(
            {
                **asdict(check.claim),
                "bound": check.claim.bound,
                "worst": w,
                "worst_n": wn,
                "worst_in_range": r,
                "worst_in_range_n": rn,
                "holds": check.holds,
                "failing_n": check.failing,
                "worst_at_claim_digits": check.rounded,
                "errors": [float(e) for e in check.errors],
            }
        )
    return records


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", metavar="PATH", type=Path, help="also write the figures here")
    args = parser.parse_args(argv)
    print(format_claims_table())
    if args.json is not None:
        args.json.write_text(json.dumps(figures(), indent=1) + "\n")
        print(f"wrote {args.json}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
