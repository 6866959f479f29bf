# SPDX-License-Identifier: Apache-2.0
"""What the tests of ``make mutants`` share (tests/test_mutation.py, the flow and the record;
tests/test_mutation_proof.py, the proofs): the build folder, the record and the docs page."""

from __future__ import annotations

import json
import os
from pathlib import Path

from sim import mutation
from sim.runner import SIM_BUILD

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "verification.md"
# builds kept between runs (the netlists are the same while the RTL is: a cache hit), one
# folder per pytest-xdist worker: ``mutation.prepare`` writes a design's folder afresh, so two
# workers preparing the same design in one folder would delete each other's files
BUILD = SIM_BUILD / "mutants" / os.environ.get("PYTEST_XDIST_WORKER", "main")
BRDF_DESIGNS = [name for name, d in mutation.DESIGNS.items() if d.top == "brdf_unit"]


def record() -> dict:
    """The record of ``make mutants`` (docs/mutants.json)."""
    return json.loads(mutation.RECORD.read_text())
