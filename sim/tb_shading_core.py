# SPDX-License-Identifier: Apache-2.0
"""cocotb bench of rtl/shading_core.v against model.render.core (run by tests/test_sim_core).

The core streams (docs/core.md): one AXI4-Stream beat per span in on ``s_axis``, one beat per
pixel out on ``m_axis`` with ``tlast`` on a span's last pixel and ``tuser`` on the pixels of a
span whose highlight the core cannot make.  cocotbext-axi drives both sides: an
``AxiStreamSource`` sends every span beat as a frame of one beat (the beat's bytes, little
endian: s_axis has no tkeep and no tlast, so a beat is width / 8 byte lanes), an
``AxiStreamSink`` takes the pixels (a frame per span: tlast ends it), an ``AxiStreamMonitor``
records them beside it; both pause at random (``set_pause_generator``: input idles, output
stalls).  Both follow ``rst_n`` (active low).

The checkers are sim/core_scoreboard.py's: ``CoreScoreboard`` holds ``core.core_pixels`` of
every span beat sent, in order; ``StreamCheck`` (a coroutine of this bench, one wake-up per
clock) reads m_axis at every rising edge: each handshake is one pixel beat, compared field by
field with the next expected pixel (tdata unpacked with ``core.PixelFormat``, tlast, tuser); a
beat offered and not taken must be offered again, unchanged, at the next edge; no X or Z on the
handshake signals after the first reset, nor on a valid beat.  The sink's and the monitor's
frames are compared with the spans too (a frame per span, the pixels' bytes, tuser on every
byte).  A mismatch names the clock, the pixel, what the RTL gave, what the model gives and the
span beat that reproduces it (``core.core_pixels([word], fmt)``).  A drain that times out (a
lost pixel, a stopped core) is reported the same way, with the pixel waited for.

Each test finishes with ``TB.finish``: the counts go to the run's summary (``BENCH_SUMMARY``,
``tests.conftest.record_sim``), and any error fails the test with the first ones.
"""

from __future__ import annotations

import json
import logging
import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import RisingEdge, SimTimeoutError, Timer, with_timeout
from cocotbext.axi import (
    AxiStreamBus,
    AxiStreamFrame,
    AxiStreamMonitor,
    AxiStreamSink,
    AxiStreamSource,
)

from model.render import core
from model.render.pipeline import METHODS
from sim import core_spans
from sim.common import bench_config, bench_rng
from sim.core_scoreboard import MAX_REPORTED, CoreScoreboard, StreamCheck, pauses

CLOCK_NS = 10
# Spans of the random test (BENCH_CORE_SPANS overrides): a few hundred, ~12 pixels each.
RANDOM_SPANS = 300


class TB:
    """The core, its stream drivers and checkers: cocotbext-axi source, sink and monitor, the
    scoreboard and the per-clock stream check."""

    def __init__(self, dut, test_name: str) -> None:
        self.dut = dut
        self.test_name = test_name
        raw = bench_config()
        self.cfg = METHODS[raw["method"]]
        self.fmt = core.SpanFormat(self.cfg, raw.get("x_width", 12), raw.get("y_width", 12))
        self.span_bytes = self.fmt.width // 8
        dut.rst_n.value = 0
        dut.s_axis_tvalid.value = 0
        dut.m_axis_tready.value = 0
        Clock(dut.clk, CLOCK_NS, unit="ns", impl="gpi").start()
        self.source = AxiStreamSource(
            AxiStreamBus.from_prefix(dut, "s_axis"), dut.clk, dut.rst_n, reset_active_level=False
        )
        m_bus = AxiStreamBus.from_prefix(dut, "m_axis")
        self.sink = AxiStreamSink(m_bus, dut.clk, dut.rst_n, reset_active_level=False)
        self.monitor = AxiStreamMonitor(m_bus, dut.clk, dut.rst_n, reset_active_level=False)
        self.ends = (self.source, self.sink, self.monitor)
        for end in self.ends:
            # They log every frame at INFO; and they are held in reset until the first reset
            # ends (rst_n starts at 0, with no edge for them to see: the outputs are X).
            end.log.setLevel(logging.WARNING)
            end.assert_reset(True)
        if self.source.byte_lanes != self.span_bytes or self.source.byte_size != 8:
            raise AssertionError(
                f"s_axis: {self.source.byte_lanes} lanes of {self.source.byte_size} bits, the "
                f"span beat is {self.span_bytes} bytes"
            )
        self.sb = CoreScoreboard(self.fmt, dut._log)
        self.check = StreamCheck(dut, self.sb)
        self.spans_sent = 0
        self.resets = 0

    # ------------------------------------------------------------------ stimulus
    def backpressure(self, rng: random.Random, idle: float, stall: float, burst: int = 1):
        """Random input idles and output stalls (0: none)."""
        self.source.set_pause_generator(pauses(rng, idle, burst) if idle else None)
        self.sink.set_pause_generator(pauses(rng, stall, burst) if stall else None)
        if not idle:
            self.source.pause = False
        if not stall:
            self.sink.pause = False

    def send(self, words: list[int]) -> None:
        """Queue span beats, one frame of one beat each, and the model's pixels for them."""
        self.sb.expect(words)
        for word in words:
            self.source.send_nowait(AxiStreamFrame(word.to_bytes(self.span_bytes, "little")))
        self.spans_sent += len(words)

    async def reset(self, cycles: int = 2) -> int:
        """rst_n low for ``cycles`` clocks (from right after an edge); every span beat and
        pixel not yet out is dropped from the expectations (the core empties).  Returns the
        pixels dropped."""
        dut = self.dut
        dut.rst_n.value = 0
        for _ in range(cycles):
            await RisingEdge(dut.clk)
        self.source.clear()  # the span beats not yet sent go with the reset
        self.frames()  # the frames complete before the reset
        dropped = self.sb.flush()
        dut.rst_n.value = 1
        for end in self.ends:
            end.assert_reset(False)  # the first reset only: the hold from __init__
        await RisingEdge(dut.clk)
        self.resets += 1
        return dropped

    def frames(self) -> None:
        """Compare the sink's and the monitor's frames received so far with the spans."""
        for who, end in (("sink", self.sink), ("monitor", self.monitor)):
            while not end.empty():
                self.sb.frame(who, end.recv_nowait(compact=False))

    async def drain(self, timeout_cycles: int | None = None) -> None:
        """Wait until every expected pixel has left m_axis (the source idle too), then the
        frames.  A core that loses a pixel or stops fails here, with the pixel it waits for
        and its span beat, instead of hanging."""
        if timeout_cycles is None:
            timeout_cycles = 40 * max(len(self.sb.pixels), 1) + 2000
        try:
            await with_timeout(self.sb.empty.wait(), timeout_cycles * CLOCK_NS, "ns")
            await with_timeout(self.source.wait(), timeout_cycles * CLOCK_NS, "ns")
        except SimTimeoutError:
            sb = self.sb
            if sb.pixels:
                p = sb.pixels[0]
                sb.error(
                    f"clock {self.check.cycle}: {len(sb.pixels)} pixels never came out in "
                    f"{timeout_cycles} clocks (the last beat taken at clock "
                    f"{self.check.last_out}), the next one pixel {p.index} (span {p.span}) "
                    f"{p.want}; {sb.span_text(p.span, p.word)}"
                )
            else:
                sb.error(
                    f"clock {self.check.cycle}: the span beats were not all taken in "
                    f"{timeout_cycles} clocks ({self.check.in_beats} of {self.spans_sent})"
                )
            self.finish()
        for _ in range(4):  # the monitor's frame of the last beat
            await RisingEdge(self.dut.clk)
        self.frames()
        for who, queue in self.sb.frames.items():
            if queue:
                self.sb.error(f"{who}: {len(queue)} spans never came out as frames")

    async def idle_check(self, cycles: int = 40) -> None:
        """No pixel beat appears once every expected pixel is out."""
        await Timer(cycles * CLOCK_NS, "ns")
        await RisingEdge(self.dut.clk)

    def finish(self) -> dict:
        """Log the counts, append them to the run's summary file, raise on any error."""
        sb, chk, test_name = self.sb, self.check, self.test_name
        record = {
            "unit": "shading_core",
            "test": test_name,
            "jobs": sb.spans_total,
            "compared": sb.compared,
            "frames": sb.frames_compared,
            "errors": len(sb.errors),
            "cycles": chk.cycle,
            "stalls": chk.stalls,
            "held": chk.held,
            "in_beats": chk.in_beats,
            "in_stalls": chk.in_stalls,
            "resets": self.resets,
            "stale_beats": sb.stale_beats,
            "first_errors": sb.errors[:MAX_REPORTED],
        }
        self.dut._log.info(
            "shading_core %s: %d spans, %d pixel beats and %d frames compared, %d clocks, "
            "%d output stalls (%d held beats checked), %d input stalls, %d errors",
            test_name,
            sb.spans_total,
            sb.compared,
            sb.frames_compared,
            chk.cycle,
            chk.stalls,
            chk.held,
            chk.in_stalls,
            len(sb.errors),
        )
        summary = os.environ.get("BENCH_SUMMARY")
        if summary:
            with open(summary, "a") as f:
                f.write(json.dumps(record) + "\n")
        if sb.errors:
            shown = "\n".join(sb.errors[:MAX_REPORTED])
            raise AssertionError(f"{len(sb.errors)} stream/pixel errors, first ones:\n{shown}")
        return record


def spans_from_env() -> int:
    raw = os.environ.get("BENCH_CORE_SPANS")
    try:
        return int(raw) if raw else RANDOM_SPANS
    except ValueError:
        raise ValueError(
            f"BENCH_CORE_SPANS={raw!r} is not allowed: it must be a span count (e.g. 300)"
        ) from None


# ---------------------------------------------------------------------- the tests


@cocotb.test(timeout_time=20, timeout_unit="ms")
async def test_random_spans_idles_and_stalls(dut):
    """(1) A few hundred random spans (1..23 pixels, every field random) in phases of random
    input idles and output stalls, light to heavy: every pixel scoreboarded."""
    tb = TB(dut, "random_spans_idles_and_stalls")
    await tb.reset()
    rng = bench_rng("random_spans")
    count = spans_from_env()
    phases = [(0.0, 0.0, 1), (0.3, 0.3, 1), (0.1, 0.6, 3), (0.6, 0.1, 3), (0.5, 0.5, 8)]
    per = -(-count // len(phases))
    for idle, stall, burst in phases:
        tb.backpressure(rng, idle, stall, burst)
        tb.send(core_spans.random_words(tb.fmt, per, rng))
        await tb.drain()
    await tb.idle_check()
    rec = tb.finish()
    assert rec["compared"] == tb.sb.sent_pixels and rec["frames"] == 2 * tb.spans_sent, rec
    assert rec["stalls"] > 0 and rec["in_stalls"] > 0, rec


@cocotb.test(timeout_time=20, timeout_unit="ms")
async def test_reset_mid_frame(dut):
    """(2) rst_n low for 1..4 clocks in the middle of a stream (span beats queued, pixels in
    the pipeline and the FIFO, random idles and stalls): no pixel beat of a span sent before
    the reset comes out after it (their rows are apart from the new ones'), and a new stream
    after the reset is scoreboarded fully.  Three times, at random points."""
    tb = TB(dut, "reset_mid_frame")
    await tb.reset()
    rng = bench_rng("reset")
    half = 1 << (tb.fmt.y_width - 1)
    halves = [range(0, half), range(half, 1 << tb.fmt.y_width)]
    dropped = []
    for r in range(3):
        # The stream cut by the reset and the one before it on one half of the rows, the one
        # after it on the other: the stale rows are the first half's.
        old_rows, new_rows = halves[r % 2], halves[1 - r % 2]
        tb.backpressure(rng, 0.2, 0.4, 2)
        tb.send(core_spans.random_words(tb.fmt, 40, rng, rows=old_rows))
        # Into the stream: some pixels out, many still inside.
        await with_timeout(_wait_compared(tb, rng.randint(20, 120)), 200, "us")
        for _ in range(rng.randint(0, 5)):
            await RisingEdge(dut.clk)
        dropped.append(await tb.reset(rng.randint(1, 4)))
        assert tb.sb.stale_rows and all(y in old_rows for y in tb.sb.stale_rows)
        tb.backpressure(rng, 0.2, 0.4, 2)
        tb.send(core_spans.random_words(tb.fmt, 30, rng, rows=new_rows))
        await tb.drain()
        await tb.idle_check()
    rec = tb.finish()
    assert all(d > 0 for d in dropped), dropped  # each reset cut a stream
    assert rec["stale_beats"] == 0 and rec["resets"] == 4, rec


async def _wait_compared(tb: TB, count: int) -> None:
    start = tb.sb.compared
    while tb.sb.compared < start + count:
        await RisingEdge(tb.dut.clk)


@cocotb.test(timeout_time=20, timeout_unit="ms")
async def test_shortest_and_longest_spans(dut):
    """(3) Spans of 1 pixel and of the longest length (cfg.gouraud.len_max pixels), random
    fields, back to back: first with no idles and no stalls (then the clocks from the first
    span beat taken to the last pixel beat are core.core_cycles: one pixel per clock, single
    pixel spans included), then with both."""
    tb = TB(dut, "shortest_and_longest_spans")
    await tb.reset()
    rng = bench_rng("lengths")
    longest = tb.cfg.gouraud.len_max
    lengths = [1] * 20 + [longest] + [1, longest, 1, 1]
    words = core_spans.random_words(tb.fmt, len(lengths), rng, lengths)
    tb.backpressure(rng, 0.0, 0.0)
    tb.send(words)
    await tb.drain()
    chk = tb.check
    cycles = chk.last_out - chk.first_in + 1
    want = core.core_cycles(sum(lengths))
    if cycles != want:
        tb.sb.error(
            f"{sum(lengths)} pixels of {len(lengths)} spans with no idle or stall took "
            f"{cycles} clocks from the first span beat to the last pixel beat, "
            f"core.core_cycles gives {want}"
        )
    tb.backpressure(rng, 0.3, 0.3, 4)
    lengths = [longest, 1, 1, longest, 1]
    tb.send(core_spans.random_words(tb.fmt, len(lengths), rng, lengths))
    await tb.drain()
    rec = tb.finish()
    assert rec["compared"] == 4 * longest + 26, rec


@cocotb.test(timeout_time=5, timeout_unit="ms")
async def test_saturating_sum(dut):
    """(4) Spans whose sum passes 255 in a channel (a bright ramp, the brightest highlight,
    the brightest diffuse term): the core gives 255 there, and the model's parts (Gouraud,
    highlight, diffuse, each alone) show the sum did pass 255 and elsewhere did not."""
    tb = TB(dut, "saturating_sum")
    await tb.reset()
    rows = core_spans.saturating_rows(tb.fmt)
    words = core_spans.words_of(tb.fmt, rows)
    fmt = tb.fmt
    clipped = unclipped = 0
    for row, word in zip(rows, words, strict=True):
        dark = {f"i_{e}{c}": 0 for e in ("start", "end") for c in range(core.CHANNELS)}
        parts = [
            {**row, "spec": 0, "diff": 0},
            {**row, **dark, "diff": 0},
            {**row, **dark, "spec": 0},
        ]
        per_part = [core.core_pixels(core_spans.words_of(fmt, [p]), fmt) for p in parts]
        for i, p in enumerate(core.core_pixels([word], fmt)):
            for ch in ("r", "g", "b"):
                total = sum(part[i][ch] for part in per_part)
                assert p[ch] == min(total, core.OUT_MAX), (row, i, ch, p, total)
                clipped += total > core.OUT_MAX
                unclipped += total < core.OUT_MAX
    assert clipped > 0 and unclipped > 0, (clipped, unclipped)
    rng = bench_rng("saturate")
    tb.backpressure(rng, 0.0, 0.0)
    tb.send(words)
    await tb.drain()
    tb.backpressure(rng, 0.4, 0.4, 2)
    tb.send(words)
    await tb.drain()
    rec = tb.finish()
    assert rec["compared"] == 2 * sum(r["l"] + 1 for r in rows), rec


@cocotb.test(timeout_time=20, timeout_unit="ms")
async def test_stalled_beats_held(dut):
    """(5) Output stalls of 1..40 clocks (tready low most of the time: the FIFO fills and
    the input stalls): every clock the bench's monitor checks that a beat offered and not
    taken is offered again at the next edge with the same tdata, tlast and tuser, and every
    pixel is scoreboarded."""
    tb = TB(dut, "stalled_beats_held")
    await tb.reset()
    rng = bench_rng("held")
    tb.backpressure(rng, 0.1, 0.75, 40)
    tb.send(core_spans.random_words(tb.fmt, 40, rng))
    await tb.drain()
    tb.backpressure(rng, 0.0, 0.5, 1)  # a stall every other clock at random
    tb.send(core_spans.random_words(tb.fmt, 40, rng))
    await tb.drain()
    rec = tb.finish()
    # Every stall was followed by the same beat again (no reset came in between).
    assert rec["held"] == rec["stalls"] and rec["stalls"] > 500, rec
    assert rec["in_stalls"] > 0, rec


@cocotb.test(timeout_time=5, timeout_unit="ms")
async def test_mismatch_report_reproduces(dut):
    """The scoreboard flags a wrong pixel and names the span beat that reproduces the RTL's
    value through the model (one expected pixel changed on purpose)."""
    tb = TB(dut, "mismatch_report_reproduces")
    await tb.reset()
    rng = bench_rng("mismatch")
    words = core_spans.random_words(tb.fmt, 4, rng, [3, 5, 2, 4])
    tb.sb.corrupt[6] = {"g": -1}  # span 1's fourth pixel
    tb.send(words)
    await tb.drain()
    errors = list(tb.sb.errors)
    assert len(errors) == 1 and "pixel 6 (span 1): g " in errors[0], errors
    want = core.core_pixels([words[1]], tb.fmt)[3]
    digits = -(-tb.fmt.width // 4)
    assert f"span beat 1 0x{words[1]:0{digits}x}" in errors[0], errors[0]
    assert f"g {want['g']} (model -1)" in errors[0], errors[0]
    tb.sb.errors.clear()
    tb.finish()
