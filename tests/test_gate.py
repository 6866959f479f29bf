# SPDX-License-Identifier: Apache-2.0
"""Gate-level simulation, a quick subset of ``make gate`` (sim/gate.py).

Each unit's Yosys netlist (generic ``synth``) replays the unit's default vector set under
Icarus with 0 mismatches, and one iCE40 netlist (``synth_ice40``, simulated with Yosys's cell
models) does too; the two RESET_ALL values are spread over the runs.  ``make gate`` runs the
whole matrix: generic, iCE40 and ECP5, RESET_ALL = 0 and 1, Icarus and Verilator.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from sim import gate

pytestmark = pytest.mark.sim

RUNS = [
    ("divider_default", "generic", 0),
    ("gouraud_default", "generic", 1),
    ("specular_default", "generic", 0),
    ("divider_default", "ice40", 1),
]


@pytest.mark.parametrize(("set_name", "target", "reset_all"), RUNS)
def test_netlist_replays_its_vector_set(
    set_name: str, target: str, reset_all: int, tmp_path: Path
) -> None:
    netlist, _ = gate.synthesise(set_name, target, reset_all, tmp_path)
    result = gate.simulate(set_name, target, reset_all, "icarus", netlist)
    assert result.passed, f"{result.line()}\n{result.log[-4000:]}"
    assert result.mismatches == 0 and result.cycles == gate.vector_sets.SETS[set_name][1]
    # a netlist, not the RTL: cells only, no behavioural always blocks of the unit
    text = netlist.read_text()
    assert "module " in text and "$readmemh" not in text
