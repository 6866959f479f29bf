"""Shared cocotb machinery for the unit benches: a driver and a protocol monitor/scoreboard.

Every unit has the same protocol (DESIGN.md): operand registers written by ``<name>_in`` +
``<name>_we`` while ``busy`` = 0, a one-cycle ``start``, ``busy`` high while the unit works,
one ``valid`` strobe per result.  A start accepted in the same cycle as a write runs on the
values the registers held before that write (the write lands for the next run).

``ProtocolMonitor`` samples the DUT after every rising edge (in ReadOnly) and checks, on its own,
whatever stimulus the test drives:

1. writes and ``start`` in a cycle with ``busy`` = 1 are ignored: it keeps a shadow copy of the
   operand registers and updates it only with accepted writes, and only an accepted start makes
   a job, whose expected results come from the golden model applied to the shadow copy;
2. each job has exactly the expected ``valid`` strobes at the expected cycles and ``busy`` high
   for exactly the expected number of cycles (the model's ``cycles()``);
3. a start in the first cycle ``busy`` is 0 is accepted like any other (back-to-back);
4. ``rst_n`` low aborts the job, clears the shadow registers and must give busy = valid = 0;
5. after the first reset no output is X or Z, in any cycle;
6. every result equals the model bit for bit; a mismatch logs the operands that reproduce it.

The test asks ``monitor.finish()`` at the end, which raises with the first mismatches.
"""

from __future__ import annotations

import json
import os
import random
from collections.abc import Callable
from dataclasses import dataclass, field

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, with_timeout

from model import fixed

CLOCK_NS = 10
MAX_REPORTED = 10
# Longer than any legal job: a 2047-interval specular line is 2052 cycles, the slowest.
WATCHDOG_CYCLES = 10_000


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


@dataclass
class Stats:
    jobs_started: int = 0
    jobs_completed: int = 0
    jobs_aborted: int = 0
    results_compared: int = 0
    writes_ignored: int = 0
    starts_ignored: int = 0
    resets: int = 0
    back_to_back: int = 0
    cycles: int = 0
    errors: list[str] = field(default_factory=list)


def as_uint(value) -> int:
    """The unsigned integer of a sampled Logic (1 bit) or LogicArray."""
    return value.to_unsigned() if hasattr(value, "to_unsigned") else int(value)


def bench_seed() -> int:
    """The random seed of this run: BENCH_SEED if given, else cocotb's (both get printed)."""
    seed = int(os.environ.get("BENCH_SEED", cocotb.RANDOM_SEED))
    cocotb.log.info("bench seed %d (rerun with BENCH_SEED=%d)", seed, seed)
    return seed


def bench_config() -> dict:
    """The unit configuration the runner built the RTL with (JSON in BENCH_CONFIG)."""
    return json.loads(os.environ["BENCH_CONFIG"])


def bench_rng(test_name: str) -> random.Random:
    return random.Random(f"{bench_seed()}-{test_name}")


class ProtocolMonitor:
    """Cycle-by-cycle checker of the load/start/busy/valid protocol against a golden model.

    ``operands`` maps each operand register name (``a`` for ``a_in``/``a_we``) to its reset
    value; ``outputs`` maps each result port to whether it is signed; ``expect`` turns a copy of
    the operand registers into the ``Job`` the unit must perform.
    """

    def __init__(
        self,
        dut,
        operands: dict[str, int],
        outputs: dict[str, bool],
        expect: Callable[[dict[str, int]], Job],
        unit: str,
    ) -> None:
        self.dut = dut
        self.unit = unit
        self.reset_values = dict(operands)
        self.outputs = outputs
        self.expect = expect
        self.shadow = dict(operands)
        self.widths = {name: len(getattr(dut, f"{name}_in")) for name in operands}
        self.out_widths = {name: len(getattr(dut, name)) for name in outputs}
        self.signed_ops: dict[str, bool] = {}
        self.job: Job | None = None
        self.stats = Stats()
        self.seen_reset = False
        # With keep_results, the RTL's outputs of every job, in order (for replays).
        self.result_log: list[list[dict[str, int]]] = []
        self.keep_results = False
        self.completed_at = -2
        inputs = [f"{n}_in" for n in operands] + [f"{n}_we" for n in operands]
        names = ("rst_n", "start", "busy", "valid", *inputs, *outputs)
        self._handles = [(name, getattr(dut, name)) for name in names]
        cocotb.start_soon(self._run())

    def corrupt_model(self, result: int, port: str, change: Callable[[int], int]) -> None:
        """Make the model wrong on purpose: ``port`` of result ``result`` (negative counts from
        the end) of every job becomes ``change(value)``.  Used to show rule 6 can fail."""
        exact = self.expect

        def corrupted(ops: dict[str, int]) -> Job:
            job = exact(ops)
            job.results[result][port] = change(job.results[result][port])
            return job

        self.expect = corrupted

    def declare_signed(self, *names: str) -> None:
        """Operand registers holding two's-complement values (for readable reports)."""
        for name in names:
            self.signed_ops[name] = True

    # ------------------------------------------------------------------ sampling
    def _sample(self) -> dict:
        return {name: handle.value for name, handle in self._handles}

    def _operand_value(self, name: str, raw) -> int:
        bits = as_uint(raw)
        if self.signed_ops.get(name):
            return fixed.from_bits(bits, self.widths[name])
        return bits

    def _output_value(self, name: str, raw) -> int:
        bits = as_uint(raw)
        return fixed.from_bits(bits, self.out_widths[name]) if self.outputs[name] else bits

    def _error(self, text: str) -> None:
        self.stats.errors.append(text)
        if len(self.stats.errors) <= MAX_REPORTED:
            self.dut._log.error("%s: %s", self.unit, text)

    def _describe(self, operands: dict[str, int]) -> str:
        return ", ".join(f"{k}={v}" for k, v in operands.items())

    # ------------------------------------------------------------------ the checks
    async def _run(self) -> None:
        prev = None
        while True:
            await RisingEdge(self.dut.clk)
            await ReadOnly()
            cur = self._sample()
            self.stats.cycles += 1
            if prev is not None:
                self._edge(prev, cur)
            prev = cur

    def _edge(self, prev: dict, cur: dict) -> None:
        """One rising edge: ``prev`` holds the inputs it sampled, ``cur`` what it produced."""
        rst_n = prev["rst_n"]
        if not rst_n.is_resolvable or int(rst_n) == 0:
            self._reset_edge(cur)
            return
        if self.seen_reset:
            self._check_known(cur)
        if not self.seen_reset:
            return

        busy_before = int(prev["busy"])
        writes = {n for n in self.shadow if int(prev[f"{n}_we"])}
        start = int(prev["start"])
        if busy_before:
            self.stats.writes_ignored += len(writes)
            self.stats.starts_ignored += start
        else:
            if start:
                if self.job is not None:
                    pending = self._describe(self.job.operands)
                    self._error(f"start accepted while a job is pending ({pending})")
                self.job = self.expect(dict(self.shadow))
                self.stats.jobs_started += 1
                if self.keep_results:
                    self.result_log.append([])
                if self.completed_at == self.stats.cycles - 1:
                    self.stats.back_to_back += 1
            for name in writes:
                self.shadow[name] = self._operand_value(name, prev[f"{name}_in"])
        self._check_job(cur, start_edge=bool(start and not busy_before))

    def _reset_edge(self, cur: dict) -> None:
        if self.job is not None:
            self.stats.jobs_aborted += 1
        self.job = None
        self.shadow = dict(self.reset_values)
        self.stats.resets += 1
        self.seen_reset = True
        if not (cur["busy"].is_resolvable and cur["valid"].is_resolvable):
            self._error("busy/valid are X or Z after a reset edge")
        elif int(cur["busy"]) or int(cur["valid"]):
            self._error("busy or valid high after a reset edge")
        for name in self.outputs:
            if not cur[name].is_resolvable or as_uint(cur[name]) != 0:
                self._error(f"output {name} = {cur[name]} after a reset edge, expected 0")

    def _check_known(self, cur: dict) -> None:
        for name in ("busy", "valid", *self.outputs):
            if not cur[name].is_resolvable:
                self._error(f"output {name} is {cur[name]} (X/Z) at cycle {self.stats.cycles}")

    def _check_job(self, cur: dict, start_edge: bool) -> None:
        busy = int(cur["busy"]) if cur["busy"].is_resolvable else -1
        valid = int(cur["valid"]) if cur["valid"].is_resolvable else -1
        job = self.job
        if job is None:
            if valid == 1:
                self._error(f"valid with no job running at cycle {self.stats.cycles}")
            if busy == 1:
                self._error(f"busy with no job running at cycle {self.stats.cycles}")
            return
        if not start_edge:
            job.offset += 1
        offset = job.offset
        expect_valid = offset in job.valid_offsets
        if valid != int(expect_valid):
            self._error(
                f"valid = {valid} at offset {offset}, expected {int(expect_valid)} "
                f"(valid offsets {job.valid_offsets[:8]}...); inputs {self._describe(job.operands)}"
            )
        if valid == 1 and job.seen < len(job.results):
            self._compare(job, cur)
        expect_busy = offset < job.busy_cycles
        if busy != int(expect_busy):
            self._error(
                f"busy = {busy} at offset {offset}, expected {int(expect_busy)} "
                f"(busy for {job.busy_cycles} cycles); inputs {self._describe(job.operands)}"
            )
        if offset >= job.busy_cycles:
            if job.seen != len(job.results):
                self._error(
                    f"{job.seen} results for {len(job.results)} expected; "
                    f"inputs {self._describe(job.operands)}"
                )
            self.stats.jobs_completed += 1
            self.completed_at = self.stats.cycles
            self.job = None

    def _compare(self, job: Job, cur: dict) -> None:
        expected = job.results[job.seen]
        got = {name: self._output_value(name, cur[name]) for name in expected}
        if self.keep_results:
            self.result_log[-1].append(got)
        if got != expected:
            self._error(
                f"result {job.seen} mismatch: got {got}, model {expected}; "
                f"reproduce with inputs {self._describe(job.operands)}"
            )
        job.seen += 1
        self.stats.results_compared += 1

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
            "ignored while busy, %d back-to-back starts, %d cycles, %d errors",
            self.unit,
            test_name,
            s.jobs_completed,
            s.results_compared,
            s.jobs_aborted,
            s.writes_ignored,
            s.starts_ignored,
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
