# SPDX-License-Identifier: Apache-2.0
"""The load/start/busy/valid protocol as a cycle-by-cycle model: what every output must be.

One implementation of the contract (docs/architecture.md, rules 1-7), used by two benches:
the cocotb ``ProtocolMonitor`` (sim/common.py) steps it with the inputs each rising edge
sampled (as its driver wrote them) and compares the DUT's outputs with its prediction for every
cycle, waking up only at an output change or where ``next_change`` says the prediction changes;
the vector soak (sim/soak.py)
predicts a random stimulus by the same rules in numba kernels (sim/soak_predict.py, checked
against this model in every cycle by tests/test_soak_fast.py; ``soak.predict`` steps this model
itself) and writes the prediction, for RESET_ALL = 0 and 1, as the expected-response file of a
plain Verilog bench.  Pure Python: no cocotb, no simulator.

Per edge, with the inputs the edge sampled (``rst_n``, ``start``, ``<op>_in``, ``<op>_we``):

* ``rst_n`` = 0 aborts any job, clears the operand registers to their reset values, gives
  busy = valid = 0, flags and strobes 0 and the data outputs undefined (``None``: the data
  path need not be reset, RESET_ALL = 0) until the next result, or 0 for an RTL built with
  RESET_ALL = 1 (``reset_all``: every register is reset);
* while busy (as predicted) writes and start are ignored (rule 1);
* otherwise a start makes a job from the operand registers as they were *before* this edge's
  writes (a write in the start cycle is for the next job), then the writes land;
* busy is 1 for the job's ``busy_cycles``; valid is 1 at its ``valid_offsets`` (0 = the cycle
  right after the start edge), and then every output takes the job's next result;
* between results every *held* output (data and flags) keeps the last result's value and every
  *strobe* output (e.g. ``last``) is 0: so every output is predicted in every cycle.

Before the first reset nothing is predicted (all ``None``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

from model.units import fixed

OutputKind = Literal["data", "flag", "strobe"]


@dataclass(frozen=True)
class Port:
    name: str
    width: int
    signed: bool = False
    # Operands: the value a reset writes.  Outputs: ignored.
    reset: int = 0
    # Outputs only: "data" (held, undefined after reset), "flag" (held, 0 after reset),
    # "strobe" (the result's value with valid, 0 otherwise).
    kind: OutputKind = "data"


@dataclass(frozen=True)
class UnitSpec:
    """The ports of one unit configuration: its operand registers and its result outputs."""

    toplevel: str
    operands: tuple[Port, ...]
    outputs: tuple[Port, ...]

    def operand(self, name: str) -> Port:
        return next(p for p in self.operands if p.name == name)

    @property
    def reset_operands(self) -> dict[str, int]:
        return {p.name: p.reset for p in self.operands}


@dataclass
class Job:
    """What one accepted start must produce, from the golden model."""

    operands: dict[str, int]
    results: list[dict[str, int]]
    busy_cycles: int
    # Offset of each valid strobe: 0 is the cycle right after the edge that accepted start.
    valid_offsets: list[int]
    offset: int = 0
    seen: int = 0
    # Edge (cycle count) that accepted the start, and whether an operand write landed with it.
    started_at: int = 0
    write_at_start: bool = False

    def __post_init__(self) -> None:
        if len(self.valid_offsets) != len(self.results):
            raise ValueError(
                f"job with {len(self.results)} results has {len(self.valid_offsets)} valid offsets"
            )
        if self.valid_offsets and max(self.valid_offsets) > self.busy_cycles:
            raise ValueError(
                f"valid offset {max(self.valid_offsets)} after busy falls ({self.busy_cycles})"
            )


@dataclass
class Stats:
    jobs_started: int = 0
    jobs_completed: int = 0
    jobs_aborted: int = 0
    results_compared: int = 0
    writes_ignored: int = 0
    starts_ignored: int = 0
    # Accepted starts with an operand write in the same edge (the div_zero class of defect).
    writes_at_start: int = 0
    resets: int = 0
    back_to_back: int = 0
    cycles: int = 0
    errors: list[str] = field(default_factory=list)


Expect = Callable[[dict[str, int]], Job]


class ProtocolModel:
    """Predicts every output of a unit, edge by edge, from its inputs and the golden model."""

    def __init__(self, spec: UnitSpec, expect: Expect, reset_all: bool = False) -> None:
        self.spec = spec
        self.expect = expect
        # The RTL's RESET_ALL: a reset clears the data outputs too (else they are don't-care)
        self.reset_all = reset_all
        self.stats = Stats()
        self.shadow: dict[str, int] | None = None  # None until the first reset
        self.job: Job | None = None
        # The job of the latest accepted start (kept after it completes, for reports).
        self.last_job: Job | None = None
        # The job whose result the held outputs show.
        self.result_job: Job | None = None
        self.busy = 0
        self.held: dict[str, int | None] = {}
        self.completed_at = -2
        self.last_result: dict[str, int] | None = None

    # ------------------------------------------------------------------ stepping
    def step(self, inputs: dict[str, int | None]) -> dict[str, int | None]:
        """One rising edge with the inputs it sampled; returns the outputs expected after it.

        ``inputs`` has ``rst_n``, ``start``, ``<op>_we`` (0/1) and ``<op>_in`` (the operand's
        value, signed for signed operands); ``None`` marks an X/Z input (only ``rst_n`` may be
        unknown, before the first reset).
        """
        s = self.stats
        s.cycles += 1
        self.last_result = None
        rst_n = inputs["rst_n"]
        if rst_n is None or rst_n == 0:
            return self._reset()
        if self.shadow is None:
            return self._unknown()
        writes = [p.name for p in self.spec.operands if inputs[f"{p.name}_we"]]
        start = bool(inputs["start"])
        new_job = False
        if self.busy:
            s.writes_ignored += len(writes)
            s.starts_ignored += int(start)
        else:
            if start:
                self.job = self.last_job = self.expect(dict(self.shadow))
                self.job.started_at = s.cycles
                self.job.write_at_start = bool(writes)
                new_job = True
                s.jobs_started += 1
                s.writes_at_start += int(bool(writes))
                if self.completed_at == s.cycles - 1:
                    s.back_to_back += 1
            for name in writes:
                self.shadow[name] = int(inputs[f"{name}_in"])  # type: ignore[arg-type]
        return self._advance(new_job)

    def _reset(self) -> dict[str, int | None]:
        if self.job is not None:
            self.stats.jobs_aborted += 1
        self.job = self.last_job = self.result_job = None
        self.busy = 0
        self.shadow = self.spec.reset_operands
        self.stats.resets += 1
        undefined = None if not self.reset_all else 0
        self.held = {p.name: (undefined if p.kind == "data" else 0) for p in self.spec.outputs}
        return {"busy": 0, "valid": 0, **self.held}

    def _unknown(self) -> dict[str, int | None]:
        return {"busy": None, "valid": None, **{p.name: None for p in self.spec.outputs}}

    def _advance(self, new_job: bool) -> dict[str, int | None]:
        job = self.job
        out: dict[str, int | None] = {"busy": 0, "valid": 0}
        strobes = {p.name: 0 for p in self.spec.outputs if p.kind == "strobe"}
        if job is not None:
            if not new_job:
                job.offset += 1
            if job.offset in job.valid_offsets:
                result = job.results[job.seen]
                job.seen += 1
                self.stats.results_compared += 1
                self.last_result = result
                self.result_job = job
                out["valid"] = 1
                for p in self.spec.outputs:
                    if p.kind == "strobe":
                        strobes[p.name] = result[p.name]
                    else:
                        self.held[p.name] = result[p.name]
            if job.offset < job.busy_cycles:
                out["busy"] = 1
            else:
                self.stats.jobs_completed += 1
                self.completed_at = self.stats.cycles
                self.job = None
        self.busy = out["busy"]  # type: ignore[assignment]
        out.update(self.held)
        out.update(strobes)
        return out

    def next_change(self) -> int | None:
        """Edges from the last one stepped to the next one after which the prediction changes
        by itself (the inputs not starting or resetting anything): 1 after a ``valid`` (it
        falls, strobes return to 0), else the running job's next ``valid`` or the edge busy
        falls; ``None`` when no job runs (every output holds).  The event-driven monitor
        (sim/common.py) wakes up there even if the RTL shows no change."""
        if self.last_result is not None:
            return 1
        job = self.job
        if job is None:
            return None
        due = job.busy_cycles - job.offset
        if job.seen < len(job.valid_offsets):
            due = min(due, job.valid_offsets[job.seen] - job.offset)
        return max(1, due)

    # ------------------------------------------------------------------ reporting
    def mismatches(
        self, expected: dict[str, int | None], got: dict[str, int | None], between: bool = False
    ) -> list[str]:
        """The errors of outputs ``got`` against ``expected`` (the last ``step``'s prediction;
        ``between``: seen between two edges), each naming the cycle, the outputs, both values
        and the inputs that reproduce the job.  Then the held outputs follow what the RTL shows,
        so one wrong value is one error and a later change of it while held is another."""
        diffs = compare(self.spec, expected, got)
        if not diffs:
            return []
        errors = []
        where = f"cycle {self.stats.cycles}" + (", between two edges" if between else "")
        result = self.last_result
        if result is not None and any(d.split(" ")[0] in result for d in diffs):
            shown = {name: got[name] for name in result}
            seen = self.last_job.seen - 1 if self.last_job is not None else 0
            errors.append(
                f"result {seen} mismatch at {where}: got {shown}, model {result}; "
                f"reproduce with inputs {self.describe()}"
            )
            diffs = [d for d in diffs if d.split(" ")[0] not in result]
        else:
            held = [d for d in diffs if d.split(" ")[0] in self.held]
            if held:
                errors.append(
                    f"{where}, between results: {'; '.join(held)} (held from the last "
                    f"result); last job: inputs {self.describe()}"
                )
            diffs = [d for d in diffs if d.split(" ")[0] not in self.held]
        if diffs:
            errors.append(f"{where}: {'; '.join(diffs)}; job: inputs {self.describe()}")
        for name in self.held:
            if expected.get(name) is not None and got.get(name) is not None:
                self.held[name] = expected[name] = got[name]
        return errors

    def describe(self, job: Job | None = None) -> str:
        """The inputs that reproduce the latest (or the given) job, for a mismatch report."""
        job = job if job is not None else self.last_job
        if job is None:
            return "no job running"
        ops = ", ".join(f"{k}={v}" for k, v in job.operands.items())
        extra = ", operand write in the start cycle" if job.write_at_start else ""
        return f"{ops} (started at cycle {job.started_at}{extra})"


def compare(
    spec: UnitSpec, expected: dict[str, int | None], got: dict[str, int | None]
) -> list[str]:
    """Names and values of the outputs that differ from a prediction (``None`` = don't care;
    a ``None`` in ``got`` is an X/Z output where a value is due)."""
    diffs = []
    for name in ("busy", "valid", *(p.name for p in spec.outputs)):
        want = expected.get(name)
        if want is None:
            continue
        have = got.get(name)
        if have != want:
            shown = "X/Z" if have is None else have
            diffs.append(f"{name} = {shown}, expected {want}")
    return diffs


def to_field(value: int, port: Port) -> int:
    """The port's bit pattern of a (signed or unsigned) value."""
    return fixed.to_bits(value, port.width) if port.signed else value


def from_field(bits: int, port: Port) -> int:
    return fixed.from_bits(bits, port.width) if port.signed else bits
