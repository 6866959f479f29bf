"""Run the specular unit's cocotb bench under Icarus for the default and a narrow configuration."""

from __future__ import annotations

import pytest

from model.units import specular
from sim.runner import run_bench
from tests.conftest import record_sim

pytestmark = pytest.mark.sim


@pytest.mark.parametrize("name", ["default", "narrow"])
def test_specular_rtl_matches_model(request, name: str) -> None:
    cfg = specular.ROM_CONFIGS[name]
    records = run_bench(
        "specular_unit", "sim.tb_specular", f"specular_{name}", cfg.hdl_parameters(), cfg
    )
    record_sim(request, records)
    assert sum(r["compared"] for r in records) > 0
    # Every n = 1..1000 went through the unit (the every-n test counts its own lines).
    every_n = [r for r in records if r["test"] == "every_n_random_lines"]
    assert every_n and every_n[0]["jobs"] >= specular.N_MAX
