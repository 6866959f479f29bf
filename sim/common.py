# SPDX-License-Identifier: Apache-2.0
"""Shared cocotb machinery for the unit benches: a driver and an event-driven protocol monitor.

Every unit has the same protocol (docs/architecture.md): operand registers written by
``<name>_in`` + ``<name>_we`` while ``busy`` = 0, a one-cycle ``start``, ``busy`` high while the
unit works, one ``valid`` strobe per result.  A start accepted in the same cycle as a write runs
on the values the registers held before that write (the write lands for the next run).

``ProtocolMonitor`` compares *every* output with the protocol model (sim/protocol.py) in *every*
cycle, whatever stimulus the test drives, without waking up in every cycle.  The driver
(``UnitTB``) writes the inputs through the monitor, which keeps them with their time, so the
inputs each edge samples are known without reading them back.  The monitor sleeps until the
first of: a value change of busy, valid or any other output (one watcher task per output), the
edge at which the model next predicts a change by itself (``ProtocolModel.next_change``: a timer)
or the edge that samples a start or reset the driver writes.  Then it reads the outputs once
(in ReadOnly) and steps the model over every edge since the last wake, in Python: in the
edges with no event every output held the value read at the last wake, and each of those
cycles is compared with the model's prediction for it; the edge of the event is compared with
the values just read.  A change between two edges is compared too.  So a glitch of one cycle
(two value changes) is caught like any other mismatch, and a change the model predicts that the
RTL does not make is caught at the predicted edge.  ``finish`` steps the edges left since the
last wake.  The rules checked are docs/architecture.md's
1-7 (writes and start ignored while busy; the expected valid strobes and busy cycles; back to
back; reset; no X or Z after reset; every result bit-exact; held outputs between results).
Icarus starts every register at X, so a RESET_ALL = 0 run shows the data outputs X between a
reset and the first result: the monitor counts those cycles (``x_data_cycles`` in the
summary), the evidence that nothing but the data outputs was left unreset; with RESET_ALL = 1
(``BENCH_RESET_ALL``, set by the runner) they are 0 from the reset on.

The test asks ``monitor.finish()`` at the end, which raises with the first mismatches.
"""

from __future__ import annotations

import json
import os
import random
from collections import deque
from collections.abc import Callable

import cocotb
from cocotb.clock import Clock
from cocotb.simtime import get_sim_time
from cocotb.triggers import FallingEdge, ReadOnly, RisingEdge, Timer, with_timeout
from cocotb.utils import get_sim_steps

from model.units import fixed
from sim import soak, units
from sim.protocol import Job, Port, ProtocolModel, Stats, from_field

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
    """The random generator of one test, seeded from the bench seed and the test's name."""
    return random.Random(f"{bench_seed()}-{test_name}")


class ProtocolMonitor:
    """Event-driven checker of every output, in every cycle, against the protocol model."""

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
        # Times the monitor woke up and read the outputs (the per-cycle monitor: every cycle).
        self.wakes = 0
        self._started = 0
        # The inputs: their handles, the values last written (for the next edge), the writes
        # not yet sampled by a checked edge (time, name, value) and the inputs as the last
        # checked edge sampled them.  X (None) until the driver first writes them.
        self._in_handles: dict[str, tuple[object, Port | None]] = {
            "rst_n": (dut.rst_n, None),
            "start": (dut.start, None),
        }
        for p in self.spec.operands:
            self._in_handles[f"{p.name}_we"] = (getattr(dut, f"{p.name}_we"), None)
            self._in_handles[f"{p.name}_in"] = (getattr(dut, f"{p.name}_in"), p)
        self._driven: dict[str, int | None] = dict.fromkeys(self._in_handles)
        self._writes: deque[tuple[int, str, int]] = deque()
        self._sampled: dict[str, int | None] = dict.fromkeys(self._in_handles)
        self._outputs: list[tuple[str, object, Port | None]] = [
            ("busy", dut.busy, None),
            ("valid", dut.valid, None),
            *((p.name, getattr(dut, p.name), p) for p in self.spec.outputs),
        ]
        inputs = [(name, handle, port) for name, (handle, port) in self._in_handles.items()]
        for name, handle, port in inputs + self._outputs:
            if port is not None and len(handle) != port.width:
                raise ValueError(
                    f"{self.unit}.{name} is {len(handle)} bits, the configuration says "
                    f"{port.width}: the RTL was built for another configuration"
                )
        self._period = get_sim_steps(CLOCK_NS, "ns")
        self._t0: int | None = None  # time of edge 0 (the first edge: not checked)
        self._done = 0  # the last edge checked
        self._got: dict[str, int | None] = {}  # the outputs read at the last wake
        self._expected: dict[str, int | None] = {}  # the model's outputs after edge _done
        self._looking = False  # a wake-up waits for ReadOnly in this time step
        self._alarms: set[int] = set()  # edges a timer will look at
        cocotb.start_soon(self._run())

    @property
    def stats(self) -> Stats:
        """The counts and errors so far, with every edge before the current time checked."""
        self._settle()
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

    # ------------------------------------------------------------------ the inputs
    @property
    def input_names(self) -> list[str]:
        """``rst_n``, ``start`` and each operand's ``<op>_we`` and ``<op>_in``."""
        return list(self._in_handles)

    def drive(self, name: str, value: int) -> None:
        """Write input ``name`` (``rst_n``, ``start``, ``<op>_we`` or ``<op>_in``, an operand as
        its signed or unsigned value) for the next edge and keep it with its time.

        The driver calls it right after a rising edge (never in ReadOnly).  A start or a reset
        wakes the monitor, which then expects a change at the edge that samples it.
        """
        handle, port = self._in_handles[name]
        if port is not None:
            bits = fixed.to_bits(int(value), port.width)
            value = from_field(bits, port)
        else:
            bits = value = int(value)
        if self._driven[name] == value:
            return
        handle.value = bits
        self._driven[name] = value
        now = get_sim_time()
        self._writes.append((now, name, value))
        if self._t0 is not None and ((name == "start" and value) or name == "rst_n"):
            # The edge that samples it may change the outputs: look there even if none does.
            self._arm((now - self._t0) // self._period + 1)

    # ------------------------------------------------------------------ sampling
    @staticmethod
    def _read(handles: list[tuple[str, object, Port | None]]) -> dict[str, int | None]:
        values: dict[str, int | None] = {}
        for name, handle, port in handles:
            # The simulator's bit string (cheaper than LogicArray.is_resolvable, bit by bit):
            # any bit other than 0 and 1 (X, Z) makes the output undefined.
            text = str(handle.value)
            if text.strip("01"):
                values[name] = None
            else:
                bits = int(text, 2)
                values[name] = from_field(bits, port) if port is not None else bits
        return values

    def _error(self, text: str) -> None:
        errors = self.model.stats.errors
        errors.append(text)
        if len(errors) <= MAX_REPORTED:
            self.dut._log.error("%s: %s", self.unit, text)

    # ------------------------------------------------------------------ waking up
    async def _run(self) -> None:
        """Edge 0, then one watcher per output: each wakes on its output's value changes."""
        await RisingEdge(self.dut.clk)
        self._t0 = get_sim_time()
        await ReadOnly()
        self._got = self._read(self._outputs)
        self.wakes += 1
        for _, handle, _ in self._outputs:
            cocotb.start_soon(self._watch(handle.value_change))
        self._arm()

    async def _watch(self, change) -> None:
        while True:
            await change
            await self._look()

    def _arm(self, edge: int | None = None) -> None:
        """Make sure the monitor looks at ``edge`` (default: the next edge at which the model
        predicts a change by itself, ``ProtocolModel.next_change``, or the next edge while a
        start or reset is being driven) even if no output changes there."""
        if edge is None:
            change = self.model.next_change()
            driven = self._driven
            if driven["rst_n"] != 1 or (driven["start"] and not self.model.busy):
                change = 1
            if change is None:
                return
            edge = self._done + change
        if edge <= self._done or any(a <= edge for a in self._alarms):
            return  # checked already, or an earlier look will arm it again
        wait = self._t0 + edge * self._period - get_sim_time()
        if wait <= 0:
            return
        self._alarms.add(edge)
        cocotb.start_soon(self._alarm(edge, wait))

    async def _alarm(self, edge: int, wait: int) -> None:
        await Timer(wait, "step")
        self._alarms.discard(edge)
        await self._look()

    async def _look(self) -> None:
        """Read the outputs once in this time step's ReadOnly and check every edge since."""
        if self._looking:
            return
        self._looking = True
        await ReadOnly()
        self._looking = False
        self.wakes += 1
        self._advance(self._read(self._outputs))
        self._arm()

    def _advance(self, got: dict[str, int | None]) -> None:
        """Check every edge since the last wake (ReadOnly): the outputs held ``self._got`` in
        the cycles without an event and show ``got`` now."""
        since, phase = divmod(get_sim_time() - self._t0, self._period)
        held = self._got
        for k in range(self._done + 1, since + 1):
            self._edge(k, got if (k == since and phase == 0) else held)
        if got != held and (phase != 0 or since == self._done):
            # A change between two edges: the cycle's prediction still holds for it.
            for text in self.model.mismatches(self._expected, got, between=True):
                self._error(text)
        self._done = max(self._done, since)
        self._got = got

    def _settle(self) -> None:
        """Check the edges before the current time since the last wake (no output changed in
        them, or the monitor would have woken up)."""
        if self._t0 is None:
            return
        last = (get_sim_time() - self._t0 - 1) // self._period
        for k in range(self._done + 1, last + 1):
            self._edge(k, self._got)
        self._done = max(self._done, last)

    # ------------------------------------------------------------------ the checks
    def _edge(self, k: int, got: dict[str, int | None]) -> None:
        """Edge ``k`` with the inputs it sampled; ``got`` the outputs after it."""
        edge_time = self._t0 + k * self._period
        writes, sampled = self._writes, self._sampled
        while writes and writes[0][0] < edge_time:
            _, name, value = writes.popleft()
            sampled[name] = value
        model = self.model
        self._expected = model.step(sampled)
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
        for text in self.model.mismatches(self._expected, got):
            self._error(text)

    # ------------------------------------------------------------------ for the test
    async def wait_idle(self) -> None:
        """Return at the first rising edge after a cycle with busy = 0.

        It watches ``busy`` itself instead of the monitor's state: the monitor may be asleep.
        It sleeps until busy falls (one trigger per job) and returns right after the next
        edge, so the caller may drive inputs, and the monitor has by then checked the cycle
        busy fell.
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
            "%d cycles (every output checked in each; the monitor woke up in %d), %d errors",
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
            self.wakes,
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
                    "wakes": self.wakes,
                    "reset_all": int(self.reset_all),
                    "x_data_cycles": self.x_data_cycles,
                    "first_errors": s.errors[:MAX_REPORTED],
                }
                f.write(json.dumps(record) + "\n")
        if s.errors:
            shown = "\n".join(s.errors[:MAX_REPORTED])
            raise AssertionError(f"{len(s.errors)} protocol/result errors, first ones:\n{shown}")
        return s


class UnitTB:
    """Drives a unit: clock, reset, operand loads and start pulses, all edge-aligned.

    Every input is written through the monitor (``ProtocolMonitor.drive``), right after a
    rising edge, so the monitor knows what each edge samples without reading it back.
    """

    def __init__(self, dut, monitor: ProtocolMonitor) -> None:
        self.dut = dut
        self.monitor = monitor
        self.operands = list(monitor.reset_values)
        self.drive = monitor.drive
        self.drive("rst_n", 0)
        self.drive("start", 0)
        for name in self.operands:
            self.drive(f"{name}_in", 0)
            self.drive(f"{name}_we", 0)
        # The clock toggles in the GPI (C), not in a Python task: no Python wake-up per edge.
        Clock(dut.clk, CLOCK_NS, unit="ns", impl="gpi").start()

    async def cycles(self, n: int = 1) -> None:
        """Wait ``n`` rising edges (called right after one): for n > 2 one timer to the middle
        of the last cycle and its closing edge instead of a wake-up per edge."""
        if n > 2:
            await Timer(n * CLOCK_NS - CLOCK_NS // 2, "ns")
            n = 1
        for _ in range(n):
            await RisingEdge(self.dut.clk)

    async def reset(self, cycles: int = 2) -> None:
        await RisingEdge(self.dut.clk)
        self.drive("rst_n", 0)
        await self.cycles(cycles)
        self.drive("rst_n", 1)
        await RisingEdge(self.dut.clk)

    def drive_operands(self, **values: int) -> None:
        """Set ``<name>_in`` and raise ``<name>_we`` for the next edge (no wait)."""
        for name, value in values.items():
            self.drive(f"{name}_we", 1)
            self.drive(f"{name}_in", value)

    def release_strobes(self) -> None:
        for name in self.operands:
            self.drive(f"{name}_we", 0)
        self.drive("start", 0)

    async def load(self, **values: int) -> None:
        """Write operand registers in one cycle (all strobes together)."""
        self.drive_operands(**values)
        await RisingEdge(self.dut.clk)
        self.release_strobes()

    async def start(self) -> None:
        self.drive("start", 1)
        await RisingEdge(self.dut.clk)
        self.drive("start", 0)

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
            self.drive("start", 1)
            await RisingEdge(self.dut.clk)
        self.release_strobes()
        await self.monitor.wait_idle()
        await self.start()
        await self.monitor.wait_idle()

    async def start_when_ready(self) -> None:
        """Hold ``start`` high until an edge accepts it (busy = 0 in the cycle before).

        Called right after a start, this lands in the first cycle busy is 0 again: the
        back-to-back case.  The cycles it is held while busy exercise rule 1 as well.  It
        sleeps until busy falls instead of looking at every edge.
        """
        self.drive("start", 1)
        await self.monitor.wait_idle()
        self.drive("start", 0)


# Cycles of each bench's random-strobe test (BENCH_STROBE_CYCLES overrides).  The bulk random
# checking is the vector soak's (sim/soak.py, tests/test_soak.py: 100 000 cycles per unit);
# these are enough to reach every corner of the protocol through cocotb.
STROBE_CYCLES = 3000


async def random_strobes(tb: UnitTB, cycles: int | None = None) -> Stats:
    """Drive the soak's random stimulus (sim/soak.py) cycle by cycle through the unit, then
    finish the monitor (rules 1-7 checked in every cycle).

    Every strobe and start at random, writes in start and busy cycles, values across 0 and at
    the extremes, short random resets; the seed is the bench's (``BENCH_SEED``).
    """
    if cycles is None:
        cycles = int(os.environ.get("BENCH_STROBE_CYCLES", STROBE_CYCLES))
    names = tb.monitor.input_names
    for inputs in soak.stimulus(tb.monitor.cfg, cycles, bench_seed()):
        for name in names:
            tb.drive(name, inputs[name])
        await RisingEdge(tb.dut.clk)
    tb.release_strobes()
    tb.drive("rst_n", 1)
    await tb.monitor.wait_idle()
    stats = tb.monitor.stats
    assert stats.writes_at_start > 0 and stats.writes_ignored > 0 and stats.starts_ignored > 0
    return tb.monitor.finish("random_strobes")
