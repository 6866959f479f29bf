# SPDX-License-Identifier: Apache-2.0
"""Print the BRDF unit's data sheet tables (docs/brdf_unit.md, between its "hardware tables"
marks): ports, parameters with their legal ranges, timing and each form's cost.

python scripts/brdf_unit.py
"""

from __future__ import annotations

from model.units.brdf import format_hardware


def main() -> None:
    print(format_hardware())


if __name__ == "__main__":
    main()
