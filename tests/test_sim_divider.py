"""Run the divider's cocotb bench under Icarus for several configurations."""

from __future__ import annotations

import pytest

from model import divider
from sim.runner import hdl_parameters, run_bench
from tests.conftest import record_sim

pytestmark = pytest.mark.sim


@pytest.mark.parametrize("name", ["article", "n4", "n16", "default"])
def test_divider_rtl_matches_model(request, name: str) -> None:
    cfg = divider.ROM_CONFIGS[name]
    params = hdl_parameters(cfg, ROM_FILE=divider.rom_path(cfg))
    records = run_bench("divider_shift", "sim.tb_divider", f"divider_{name}", params, cfg)
    record_sim(request, records)
    assert sum(r["compared"] for r in records) > 0
