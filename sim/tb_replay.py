# SPDX-License-Identifier: Apache-2.0
"""Replay bench: push a file of operand sets through one unit and record what the RTL outputs.

The scene co-simulation uses it: ``BENCH_JOBS`` names a JSON file ``{"jobs": [{operand: value}]}``,
``BENCH_OUT`` the JSON file the RTL's outputs go to (one list of output dicts per job).  The
unit's own bench class drives it, so the protocol monitor checks every result against the model
as usual; the replay adds the throughput (jobs, results and wall time) to the output file.
"""

from __future__ import annotations

import importlib
import json
import os
import time

import cocotb

# Toplevel -> (bench module, bench class): each class takes the dut and reads BENCH_CONFIG.
BENCHES = {
    "divider_shift": ("sim.tb_divider", "DividerTB"),
    "gouraud_segment": ("sim.tb_gouraud", "GouraudTB"),
    "specular_unit": ("sim.tb_specular", "SpecularTB"),
}


def bench_class(toplevel: str):
    module, name = BENCHES[toplevel]
    return getattr(importlib.import_module(module), name)


@cocotb.test()
async def test_replay(dut):
    tb = bench_class(dut._name)(dut)
    with open(os.environ["BENCH_JOBS"]) as f:
        jobs = json.load(f)["jobs"]
    tb.monitor.keep_results = True
    await tb.reset()
    began = time.perf_counter()
    for operands in jobs:
        await tb.run(**operands)
    wall = time.perf_counter() - began
    stats = tb.monitor.finish("replay")
    assert stats.jobs_completed == len(jobs), (stats.jobs_completed, len(jobs))
    with open(os.environ["BENCH_OUT"], "w") as f:
        json.dump(
            {
                "outputs": tb.monitor.result_log,
                "results": stats.results_compared,
                "cycles": stats.cycles,
                "wall_s": wall,
            },
            f,
        )
