# SPDX-License-Identifier: Apache-2.0
"""The two tiers of the suite (tests/tiers.py): every slow name is a real test and a stale one
is refused."""

from __future__ import annotations

import re
from pathlib import Path

from tests.tiers import SIM_CHOSEN, SLOW, classify, sim_fixed

ROOT = Path(__file__).resolve().parent.parent


def test_every_slow_name_is_a_test_function() -> None:
    """Statically (the collection hook in conftest.py also refuses a stale name, parameters
    included, in every run that collects its file)."""
    for key in SLOW:
        file, name = key.split("::")
        text = (ROOT / file).read_text()
        assert f"def {name.split('[')[0]}(" in text, key


def test_a_renamed_slow_test_is_refused() -> None:
    file = next(iter(SLOW)).split("::")[0]
    slow, stale = classify([f"{file}::test_that_is_there", "tests/test_other.py::test_x"])
    assert slow == set()
    assert set(stale) == {k for k in SLOW if k.startswith(file + "::")}


def test_sim_chosen_names_exactly_the_files_that_run_the_simulator_sim_names() -> None:
    """A test file that starts cocotb (``run_bench``) or the units' scene co-simulation
    (``sim.scene_cosim``; the core's, ``sim.core_run``, names its simulator) reads SIM: it
    must be in ``SIM_CHOSEN``, or CI's slow tier would leave it out as ``sim_fixed`` and run
    it under Verilator only.  Read statically."""
    reads_sim = set()
    for path in sorted((ROOT / "tests").glob("test_*.py")):
        text = path.read_text()
        if "pytest.mark.sim" not in text or path.name == Path(__file__).name:
            continue
        if re.search(r"\brun_bench\(", text) or "scene_cosim" in text:
            reads_sim.add(f"tests/{path.name}")
    # test_sim_verilator.py runs the benches under Verilator whatever SIM says
    assert reads_sim - {"tests/test_sim_verilator.py"} == set(SIM_CHOSEN)


def test_a_sim_test_outside_sim_chosen_is_sim_fixed() -> None:
    assert not sim_fixed(f"{SIM_CHOSEN[0]}::test_x")
    assert sim_fixed("tests/test_soak.py::test_soak_every_output_every_cycle[divider_default]")
