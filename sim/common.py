# SPDX-License-Identifier: Apache-2.0
"""Shared cocotb machinery for the unit benches: a driver and a protocol monitor/scoreboard.

Every unit has the same protocol (docs/architecture.md): operand registers written by
``<name>_in`` + ``<name>_we`` while ``busy`` = 0, a one-cycle ``start``, ``busy`` high while the
unit works, one ``valid`` strobe per result.  A start accepted in the same cycle as a write runs
on the values the registers held before that write (the write lands for the next run).

``ProtocolMonitor`` samples the DUT after every rising edge (in ReadOnly), steps the protocol
model (sim/protocol.py) with the inputs that edge sampled, and compares *every* output with the
model's prediction in *every* cycle, whatever stimulus the test drives:

1. writes and ``start`` in a cycle with ``busy`` = 1 are ignored (the model keeps the operand
   registers and only an accepted start makes a job, from the golden model);
2. each job has exactly the expected ``valid`` strobes at the expected cycles and ``busy`` high
   for exactly the expected number of cycles (the model's ``cycles()``);
3. a start in the first cycle ``busy`` is 0 is accepted like any other (back-to-back);
4. ``rst_n`` low aborts the job, clears the operand registers and gives busy = valid = 0 and
   the flags 0;
5. after the first reset busy, valid and the flags are never X or Z, and data outputs are
   defined from the first result on; with RESET_ALL = 1 (``BENCH_RESET_ALL``, set by the
   runner to the value the RTL was built with) they are 0 from the reset on.  Icarus starts
   every register at X, so a RESET_ALL = 0 run shows the data outputs X between the reset and
   the first result: the monitor counts those cycles (``x_data_cycles`` in the summary), the
   evidence that nothing but the data outputs was left unreset;
6. every result equals the model bit for bit; a mismatch logs the operands that reproduce it;
7. between results every output holds the last result (strobes such as ``last`` are 0), so a
   flag that belongs to another job than its result is caught in the cycle it appears.

The test asks ``monitor.finish()`` at the end, which raises with the first mismatches.
"""

from __future__ import annotations

import json
import os
import random
from collections.abc import Callable

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, with_timeout

from model.units import fixed
from sim import soak, units
from sim.protocol import Job, Port, ProtocolModel, Stats, compare, from_field

__all__ = [
    "Job",
    "ProtocolMonitor",
    "Stats",
    "UnitTB",
    "bench_config",
    "bench_reset_all",
    "bench_rng",
    "bench_seed",
    "random_strobes",
]

CLOCK_NS = 10
MAX_REPORTED = 10
# Longer than any legal job: a 2047-interval specular line is 2052 cycles, the slowest.
WATCHDOG_CYCLES = 10_000


def as_uint(value) -> int:
    """The unsigned integer of a sampled Logic (1 bit) or LogicArray."""
    return value.to_unsigned() if hasattr(value, "to_unsigned") else int(value)


def bench_seed() -> int:
    """The random seed of this run: BENCH_SEED if given, else cocotb's (both get printed)."""
    raw = os.environ.get("BENCH_SEED")
    if raw is None:
        seed = int(cocotb.RANDOM_SEED)
    else:
        try:
            seed = int(raw, 0)
        except ValueError:
            raise ValueError(
                f"BENCH_SEED={raw!r} is not allowed: it must be an integer (e.g. BENCH_SEED=1234)"
            ) from None
    cocotb.log.info("bench seed %d (rerun with BENCH_SEED=%d)", seed, seed)
    return seed


def bench_config() -> dict:
    """The unit configuration the runner built the RTL with (JSON in BENCH_CONFIG)."""
    return json.loads(os.environ["BENCH_CONFIG"])


def bench_reset_all() -> bool:
    """The RESET_ALL the runner built the RTL with (BENCH_RESET_ALL; 0 when unset)."""
    return os.environ.get("BENCH_RESET_ALL", "0") not in ("", "0")


def bench_rng(test_name: str) -> random.Random:
    return random.Random(f"{bench_seed()}-{test_name}")


class ProtocolMonitor:
    """Cycle-by-cycle checker of every output against the protocol model of one unit."""

    def __init__(self, dut, cfg: units.UnitConfig) -> None:
        self.dut = dut
        self.cfg = cfg
        self.spec = units.spec(cfg)
        self.unit = self.spec.toplevel
        self.reset_all = bench_reset_all()
        self.model = ProtocolModel(self.spec, units.expect(cfg), self.reset_all)
        # Cycles after a reset with a data output X (RTL with an unreset data path, Icarus)
        self.x_data_cycles = 0
        self.reset_values = self.spec.reset_operands
        # With keep_results, the RTL's outputs of every job, in order (for replays).
        self.result_log: list[list[dict[str, int]]] = []
        self.keep_results = False
        self._started = 0
        self._inputs: list[tuple[str, object, Port | None]] = [
            ("rst_n", dut.rst_n, None),
            ("start", dut.start, None),
        ]
        for p in self.spec.operands:
            self._inputs.append((f"{p.name}_we", getattr(dut, f"{p.name}_we"), None))
            self._inputs.append((f"{p.name}_in", getattr(dut, f"{p.name}_in"), p))
        self._outputs: list[tuple[str, object, Port | None]] = [
            ("busy", dut.busy, None),
            ("valid", dut.valid, None),
            *((p.name, getattr(dut, p.name), p) for p in self.spec.outputs),
        ]
        for name, handle, port in self._outputs + self._inputs:
            if port is not None and len(handle) != port.width:
                raise ValueError(
                    f"{self.unit}.{name} is {len(handle)} bits, the configuration says "
                    f"{port.width}: the RTL was built for another configuration"
                )
        cocotb.start_soon(self._run())

    @property
    def stats(self) -> Stats:
        return self.model.stats

    def corrupt_model(self, result: int, port: str, change: Callable[[int], int]) -> None:
        """Make the model wrong on purpose: ``port`` of result ``result`` (negative counts from
        the end) of every job becomes ``change(value)``.  Used to show rule 6 can fail."""
        exact = self.model.expect

        def corrupted(ops: dict[str, int]) -> Job:
            job = exact(ops)
            job.results[result][port] = change(job.results[result][port])
            return job

        self.model.expect = corrupted

    # ------------------------------------------------------------------ sampling
    @staticmethod
    def _read(handles: list[tuple[str, object, Port | None]]) -> dict[str, int | None]:
        values: dict[str, int | None] = {}
        for name, handle, port in handles:
            raw = handle.value
            if not raw.is_resolvable:
                values[name] = None
            else:
                bits = as_uint(raw)
                values[name] = from_field(bits, port) if port is not None else bits
        return values

    def _error(self, text: str) -> None:
        errors = self.stats.errors
        errors.append(text)
        if len(errors) <= MAX_REPORTED:
            self.dut._log.error("%s: %s", self.unit, text)

    # ------------------------------------------------------------------ the checks
    async def _run(self) -> None:
        inputs = None
        while True:
            await RisingEdge(self.dut.clk)
            await ReadOnly()
            if inputs is not None:
                self._edge(inputs, self._read(self._outputs))
            inputs = self._read(self._inputs)

    def _edge(self, inputs: dict[str, int | None], got: dict[str, int | None]) -> None:
        """One rising edge: ``inputs`` as it sampled them, ``got`` the outputs after it."""
        model = self.model
        expected = model.step(inputs)
        result = model.last_result
        if result is not None and self.keep_results:
            if model.stats.jobs_started != self._started:
                self._started = model.stats.jobs_started
                self.result_log.append([])
            self.result_log[-1].append({name: got[name] for name in result})
        if model.shadow is not None and any(
            got[p.name] is None for p in self.spec.outputs if p.kind == "data"
        ):
            self.x_data_cycles += 1
        diffs = compare(self.spec, expected, got)
        if not diffs:
            return
        cycle = model.stats.cycles
        if result is not None and any(d.split(" ")[0] in result for d in diffs):
            job = model.last_job
            shown = {name: got[name] for name in result}
            self._error(
                f"result {job.seen - 1} mismatch at cycle {cycle}: got {shown}, model {result}; "
                f"reproduce with inputs {model.describe()}"
            )
            diffs = [d for d in diffs if d.split(" ")[0] not in result]
        else:
            held = [d for d in diffs if d.split(" ")[0] in model.held]
            if held:
                self._error(
                    f"cycle {cycle}, between results: {'; '.join(held)} (held from the last "
                    f"result); last job: inputs {model.describe()}"
                )
            diffs = [d for d in diffs if d.split(" ")[0] not in model.held]
        if diffs:
            self._error(f"cycle {cycle}: {'; '.join(diffs)}; job: inputs {model.describe()}")
        # Re-synchronise the held outputs with what the RTL shows, so one wrong value is one
        # error and a later change of it while held is another.
        for name in model.held:
            if expected.get(name) is not None and got.get(name) is not None:
                model.held[name] = got[name]

    # ------------------------------------------------------------------ for the test
    async def wait_idle(self) -> None:
        """Return at the first rising edge after a cycle with busy = 0.

        It watches ``busy`` itself instead of the monitor's state: cocotb wakes the monitor
        and the driver in ReadOnly in no fixed order.  It sleeps until busy falls (one trigger
        per job, not two per cycle) and returns right after the next edge, so the caller may
        drive inputs, and the monitor has by then checked the cycle busy fell.
        """
        await ReadOnly()
        if int(self.dut.busy.value):
            # A busy that never falls fails the test instead of hanging it (no legal job of
            # any unit takes WATCHDOG_CYCLES; the monitor has reported the busy error by then).
            await with_timeout(FallingEdge(self.dut.busy), WATCHDOG_CYCLES * CLOCK_NS, "ns")
        await RisingEdge(self.dut.clk)

    def finish(self, test_name: str) -> Stats:
        """Log the counts, append them to the run's summary file, raise on any error."""
        s = self.stats
        self.dut._log.info(
            "%s %s: %d jobs, %d results compared, %d aborted by reset, %d writes and %d starts "
            "ignored while busy, %d writes with an accepted start, %d back-to-back starts, "
            "%d cycles (every output checked in each), %d errors",
            self.unit,
            test_name,
            s.jobs_completed,
            s.results_compared,
            s.jobs_aborted,
            s.writes_ignored,
            s.starts_ignored,
            s.writes_at_start,
            s.back_to_back,
            s.cycles,
            len(s.errors),
        )
        summary = os.environ.get("BENCH_SUMMARY")
        if summary:
            with open(summary, "a") as f:
                record = {
                    "unit": self.unit,
                    "test": test_name,
                    "jobs": s.jobs_completed,
                    "compared": s.results_compared,
                    "errors": len(s.errors),
                    "cycles": s.cycles,
                    "reset_all": int(self.reset_all),
                    "x_data_cycles": self.x_data_cycles,
                }
                f.write(json.dumps(record) + "\n")
        if s.errors:
            shown = "\n".join(s.errors[:MAX_REPORTED])
            raise AssertionError(f"{len(s.errors)} protocol/result errors, first ones:\n{shown}")
        return s


class UnitTB:
    """Drives a unit: clock, reset, operand loads and start pulses, all edge-aligned."""

    def __init__(self, dut, monitor: ProtocolMonitor) -> None:
        self.dut = dut
        self.monitor = monitor
        self.operands = list(monitor.reset_values)
        dut.rst_n.value = 0
        dut.start.value = 0
        for name in self.operands:
            getattr(dut, f"{name}_in").value = 0
            getattr(dut, f"{name}_we").value = 0
        cocotb.start_soon(Clock(dut.clk, CLOCK_NS, unit="ns").start())

    async def cycles(self, n: int = 1) -> None:
        for _ in range(n):
            await RisingEdge(self.dut.clk)

    async def reset(self, cycles: int = 2) -> None:
        await RisingEdge(self.dut.clk)
        self.dut.rst_n.value = 0
        await self.cycles(cycles)
        self.dut.rst_n.value = 1
        await RisingEdge(self.dut.clk)

    def drive_operands(self, **values: int) -> None:
        """Set ``<name>_in`` and raise ``<name>_we`` for the next edge (no wait)."""
        for name, value in values.items():
            port = getattr(self.dut, f"{name}_in")
            getattr(self.dut, f"{name}_we").value = 1
            port.value = fixed.to_bits(int(value), len(port))

    def release_strobes(self) -> None:
        for name in self.operands:
            getattr(self.dut, f"{name}_we").value = 0
        self.dut.start.value = 0

    async def load(self, **values: int) -> None:
        """Write operand registers in one cycle (all strobes together)."""
        self.drive_operands(**values)
        await RisingEdge(self.dut.clk)
        self.release_strobes()

    async def start(self) -> None:
        self.dut.start.value = 1
        await RisingEdge(self.dut.clk)
        self.dut.start.value = 0

    async def run(self, **values: int) -> None:
        """Load, start, and wait until the job is finished (busy low again)."""
        await self.load(**values)
        await self.start()
        await self.monitor.wait_idle()

    async def hammer_while_busy(
        self, cycles: int, random_operands: Callable[[], dict[str, int]]
    ) -> None:
        """Rule 1 probe, called right after an accepted ``start``.

        In each of the job's ``cycles`` busy cycles it drives random operand writes and start;
        then it starts again without loading, so the monitor (whose shadow registers ignore the
        busy-time writes) checks that neither the job nor the rerun saw them.
        """
        for _ in range(cycles):
            self.drive_operands(**random_operands())
            self.dut.start.value = 1
            await RisingEdge(self.dut.clk)
        self.release_strobes()
        await self.monitor.wait_idle()
        await self.start()
        await self.monitor.wait_idle()

    async def start_when_ready(self) -> None:
        """Hold ``start`` high until an edge accepts it (busy = 0 in the cycle before).

        Called right after a start, this lands in the first cycle busy is 0 again: the
        back-to-back case.  The cycles it is held while busy exercise rule 1 as well.
        """
        self.dut.start.value = 1
        while True:
            await ReadOnly()
            ready = int(self.dut.busy.value) == 0
            await RisingEdge(self.dut.clk)
            if ready:
                break
        self.dut.start.value = 0


# Cycles of each bench's random-strobe test (BENCH_STROBE_CYCLES overrides; the vector soak
# runs 100k).
STROBE_CYCLES = 3000


async def random_strobes(tb: UnitTB, cycles: int | None = None) -> Stats:
    """Drive the soak's random stimulus (sim/soak.py) cycle by cycle through the unit, then
    finish the monitor (rules 1-7 checked in every cycle).

    Every strobe and start at random, writes in start and busy cycles, values across 0 and at
    the extremes, short random resets; the seed is the bench's (``BENCH_SEED``).
    """
    if cycles is None:
        cycles = int(os.environ.get("BENCH_STROBE_CYCLES", STROBE_CYCLES))
    for inputs in soak.stimulus(tb.monitor.cfg, cycles, bench_seed()):
        tb.dut.rst_n.value = inputs["rst_n"]
        tb.dut.start.value = inputs["start"]
        for port in tb.monitor.spec.operands:
            getattr(tb.dut, f"{port.name}_we").value = inputs[f"{port.name}_we"]
            getattr(tb.dut, f"{port.name}_in").value = fixed.to_bits(
                inputs[f"{port.name}_in"], port.width
            )
        await RisingEdge(tb.dut.clk)
    tb.release_strobes()
    tb.dut.rst_n.value = 1
    await tb.monitor.wait_idle()
    stats = tb.monitor.stats
    assert stats.writes_at_start > 0 and stats.writes_ignored > 0 and stats.starts_ignored > 0
    return tb.monitor.finish("random_strobes")
