"""Run the segment Gouraud unit's cocotb bench under Icarus for several configurations."""

from __future__ import annotations

import pytest

from model.units.gouraud import GouraudConfig
from sim.runner import hdl_parameters, run_bench
from tests.conftest import record_sim

pytestmark = pytest.mark.sim

# P = 2, 4, 8 with the default 12 fraction bits and a coarse 4; P = 16 exercises the
# increment network's second adder level (11 = 10+1, 13 = 12+1).
CONFIGS = {f"p{p}_f{f}": GouraudConfig(p=p, i_frac=f) for p in (2, 4, 8) for f in (12, 4)}
CONFIGS["p16_f12"] = GouraudConfig(p=16, i_frac=12)


@pytest.mark.parametrize("name", list(CONFIGS))
def test_gouraud_rtl_matches_model(request, name: str) -> None:
    cfg = CONFIGS[name]
    params = hdl_parameters(cfg)
    records = run_bench("gouraud_segment", "sim.tb_gouraud", f"gouraud_{name}", params, cfg)
    record_sim(request, records)
    assert len(records) == 9 and all(r["errors"] == 0 for r in records), records
    assert sum(r["compared"] for r in records) > 0
