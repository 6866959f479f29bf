# SPDX-License-Identifier: Apache-2.0
"""The benches' expectation, driven without a simulator, for the contract tests (docs/*.md).

Every cocotb test (``sim/common.py``'s ProtocolMonitor) and every vector soak (``sim/soak.py``)
compares the RTL, output by output and cycle by cycle, with the protocol model of
``sim/protocol.py`` fed by the golden model through ``sim/units.py``.  The contract tests step
that same model here to show that what the benches expect *is* what the documents say (busy
for exactly ``cycles()``, ``valid`` at the documented offsets, outputs held between results,
reset clearing the operand registers ...); the benches then hold the RTL to it.
"""

from __future__ import annotations

from sim import units
from sim.protocol import ProtocolModel


class Drive:
    """Feeds the protocol model of one unit configuration edge by edge and keeps its outputs.

    ``outputs[i]`` is what every output must be after edge ``i`` (busy, valid and the unit's
    result outputs); ``None`` is a don't-care (data outputs after a reset).
    """

    def __init__(self, cfg: units.UnitConfig) -> None:
        self.cfg = cfg
        self.spec = units.spec(cfg)
        self.model = ProtocolModel(self.spec, units.expect(cfg))
        self.outputs: list[dict[str, int | None]] = []

    def edge(self, start: int = 0, rst_n: int = 1, **writes: int) -> dict[str, int | None]:
        """One rising edge; ``writes`` are operand values whose write strobe is high."""
        inputs: dict[str, int | None] = {"rst_n": rst_n, "start": start}
        for p in self.spec.operands:
            inputs[f"{p.name}_we"] = int(p.name in writes)
            inputs[f"{p.name}_in"] = writes.get(p.name, 0)
        out = self.model.step(inputs)
        self.outputs.append(out)
        return out

    def reset(self, cycles: int = 2) -> None:
        for _ in range(cycles):
            self.edge(rst_n=0)

    def idle(self, cycles: int) -> None:
        for _ in range(cycles):
            self.edge()

    def job(self, tail: int = 3, **operands: int) -> list[dict[str, int | None]]:
        """Load ``operands`` (one edge), start (the next edge), then ``tail`` idle edges after
        busy falls.  Returns the outputs from the start edge on: index 0 is the cycle right
        after the edge that accepted start (offset 0 of ``valid_offsets``)."""
        if operands:
            self.edge(**operands)
        first = len(self.outputs)
        self.edge(start=1)
        while self.outputs[-1]["busy"]:
            self.edge()
        self.idle(tail)
        return self.outputs[first:]


def column(outputs: list[dict[str, int | None]], name: str) -> list[int | None]:
    return [o[name] for o in outputs]


def ones(values: list[int | None]) -> list[int]:
    """Indices where ``values`` is 1."""
    return [i for i, v in enumerate(values) if v == 1]
