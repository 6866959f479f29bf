# SPDX-License-Identifier: Apache-2.0
"""The shading core bench's checkers (sim/tb_shading_core.py): the scoreboard of the pixel
beats against ``model.render.core.core_pixels`` and the bench's own per-clock m_axis monitor.

``CoreScoreboard`` holds the model's pixels of every span beat sent, in order, and compares
each pixel beat taken (tdata unpacked with ``core.PixelFormat``, tlast, tuser) and each frame
of the cocotbext-axi sink and monitor (one per span: the pixels' bytes, tuser on every byte);
a mismatch names the clock, the pixel, what the RTL gave, what the model gives and the span
beat that reproduces it (``core.core_pixels([word], fmt)``).  After a reset it drops what it
expected (the core empties) and the rows of the dropped spans become stale: a beat on one of
them came from before the reset.

``StreamCheck`` wakes at every rising edge and reads m_axis: a handshake is one pixel beat for
the scoreboard; a beat offered and not taken must be offered again, unchanged, at the next
edge (AXI4-Stream: tvalid held until tready, tdata, tlast and tuser stable); no X or Z on the
handshake signals from the first edge after one that samples rst_n low, nor on a valid beat.
"""

from __future__ import annotations

import random
from collections import deque
from dataclasses import dataclass

import cocotb
from cocotb.triggers import Event, RisingEdge
from cocotbext.axi import AxiStreamFrame

from model.render import core

MAX_REPORTED = 10


@dataclass
class Pixel:
    """One pixel the model expects: its fields (``core.core_pixels``), its span and place."""

    want: dict[str, int]
    span: int  # index of the span beat among the ones sent since the last reset
    index: int  # pixel index in that stream
    word: int  # the span beat


class CoreScoreboard:
    """The pixels the model gives for the span beats sent, compared beat by beat and frame by
    frame with what leaves m_axis."""

    def __init__(self, fmt: core.SpanFormat, log) -> None:
        self.fmt = fmt
        self.layout = fmt.layout()
        self.pix = core.PixelFormat(fmt.x_width, fmt.y_width)
        self.pix_layout = self.pix.layout()
        self.pix_bytes = self.pix.width // 8
        self.log = log
        self.errors: list[str] = []
        self.pixels: deque[Pixel] = deque()
        # Per consumer of frames (the sink and the monitor): (span, word, bytes, n_err) of
        # every span not yet received as a frame.
        self.frames: dict[str, deque] = {"sink": deque(), "monitor": deque()}
        self.words: list[int] = []  # the span beats sent since the last reset
        self.sent_pixels = 0
        self.compared = 0  # pixel beats compared
        self.frames_compared = 0
        self.spans_total = 0
        # Rows (y) no pixel beat may carry: the spans sent before a reset.
        self.stale_rows: set[int] = set()
        self.stale_beats = 0
        self.empty = Event()
        self.empty.set()
        # Test hook: change the model's pixel (index in the stream) to show a mismatch report.
        self.corrupt: dict[int, dict[str, int]] = {}

    # ------------------------------------------------------------------ expectations
    def expect(self, words: list[int]) -> None:
        """Add the model's pixels of ``words`` (sent in this order after those before)."""
        pixels = core.core_pixels(words, self.fmt)
        at = 0
        for word in words:
            span = len(self.words)
            self.words.append(word)
            n_px = core.unpack(self.layout, word)["l"] + 1
            data = bytearray()
            for p in pixels[at : at + n_px]:
                index = self.sent_pixels
                self.sent_pixels += 1
                want = {**p, **self.corrupt.get(index, {})}
                self.pixels.append(Pixel(want, span, index, word))
                data += core.pixel_word(p, self.pix).to_bytes(self.pix_bytes, "little")
            for queue in self.frames.values():
                queue.append((span, word, bytes(data), pixels[at]["n_err"]))
            at += n_px
        self.spans_total += len(words)
        if self.pixels:
            self.empty.clear()

    def flush(self) -> int:
        """Drop every expectation (a reset empties the core); the rows of the spans sent since
        the last reset become the stale rows (no later beat may carry one: the next stream
        uses other rows).  Returns the pixels dropped."""
        dropped = len(self.pixels)
        self.stale_rows = {core.unpack(self.layout, word)["y"] for word in self.words}
        self.pixels.clear()
        for queue in self.frames.values():
            queue.clear()
        self.words = []
        self.sent_pixels = 0
        self.empty.set()
        return dropped

    # ------------------------------------------------------------------ the checks
    def error(self, text: str) -> None:
        self.errors.append(text)
        if len(self.errors) <= MAX_REPORTED:
            self.log.error("shading_core: %s", text)

    def span_text(self, span: int, word: int) -> str:
        digits = -(-self.fmt.width // 4)
        return f"span beat {span} 0x{word:0{digits}x} = {core.unpack(self.layout, word)}"

    def beat(self, cycle: int, tdata: int, tlast: int, tuser: int) -> None:
        """One pixel beat taken at clock ``cycle``."""
        got = {**core.unpack(self.pix_layout, tdata), "last": tlast, "n_err": tuser}
        if got["y"] in self.stale_rows:
            self.stale_beats += 1
            self.error(f"clock {cycle}: pixel beat {got} belongs to a span sent before the reset")
        if not self.pixels:
            self.error(f"clock {cycle}: pixel beat {got} with no pixel expected")
            return
        p = self.pixels.popleft()
        self.compared += 1
        if got != p.want:
            diff = ", ".join(
                f"{k} {got[k]} (model {p.want[k]})" for k in p.want if got[k] != p.want[k]
            )
            self.error(
                f"clock {cycle}: pixel {p.index} (span {p.span}): {diff}; RTL {got}, model "
                f"{p.want}; {self.span_text(p.span, p.word)}"
            )
        if not self.pixels:
            self.empty.set()

    def frame(self, who: str, frame: AxiStreamFrame) -> None:
        """One frame of the sink or the monitor (not compacted: tuser a list, one per byte):
        one span's pixels, the span's tuser on every byte."""
        queue = self.frames[who]
        data = bytes(frame.tdata)
        if not queue:
            self.error(f"{who}: a frame of {len(data)} bytes with no span expected")
            return
        span, word, want, n_err = queue.popleft()
        self.frames_compared += 1
        tuser = set(frame.tuser)
        if data != want or tuser != {n_err} or len(frame.tuser) != len(data):
            self.error(
                f"{who}: frame of span {span} has {len(data)} bytes, tuser {sorted(tuser)}, "
                f"the model {len(want)} bytes, tuser {n_err}"
                f"{'' if data == want else ', the bytes differ'}; {self.span_text(span, word)}"
            )


class StreamCheck:
    """The bench's own m_axis monitor: every rising edge, the handshake, the AXI4-Stream rule
    (a beat offered and not taken is offered again unchanged), and no X or Z after reset."""

    def __init__(self, dut, scoreboard: CoreScoreboard) -> None:
        self.dut = dut
        self.sb = scoreboard
        self.cycle = 0
        self.armed = False  # an edge sampled rst_n low: the outputs are defined from the next
        self.stalls = 0  # edges with a pixel beat offered and not taken
        self.held = 0  # of those, the ones followed by the same beat again (the rule checked)
        self.in_beats = 0  # span beats taken
        self.in_stalls = 0  # edges with a span beat offered and not taken
        self.first_in: int | None = None  # clock of the first span beat taken
        self.last_out: int | None = None  # clock of the last pixel beat taken
        self._task = cocotb.start_soon(self._run())

    @staticmethod
    def _bits(handle) -> str:
        return str(handle.value)

    async def _run(self) -> None:
        dut = self.dut
        m_valid, m_ready, m_data = dut.m_axis_tvalid, dut.m_axis_tready, dut.m_axis_tdata
        m_last, m_user = dut.m_axis_tlast, dut.m_axis_tuser
        s_valid, s_ready = dut.s_axis_tvalid, dut.s_axis_tready
        bits = self._bits
        hold: tuple[str, str, str] | None = None  # the beat stalled at the last edge
        hold_cycle = 0
        while True:
            await RisingEdge(dut.clk)
            self.cycle += 1
            cycle = self.cycle
            rst = bits(dut.rst_n)
            if not self.armed:
                # Defined from the edge after the first one that samples rst_n low.
                self.armed = rst == "0"
                continue
            valid, ready = bits(m_valid), bits(m_ready)
            for name, value in (("m_axis_tvalid", valid), ("s_axis_tready", bits(s_ready))):
                if value not in ("0", "1"):
                    self.sb.error(f"clock {cycle}: {name} = {value} after reset")
            beat = (bits(m_data), bits(m_last), bits(m_user)) if valid == "1" else None
            if beat is not None and any(b.strip("01") for b in beat):
                self.sb.error(f"clock {cycle}: a valid pixel beat with X or Z: {beat}")
                beat = None
            if hold is not None:
                # Offered and not taken at the last edge, out of reset there: the same beat.
                if beat != hold:
                    self.sb.error(
                        f"clock {cycle}: the pixel beat stalled at clock {hold_cycle} "
                        f"(tdata 0x{int(hold[0], 2):x}, tlast {hold[1]}, tuser {hold[2]}) "
                        + (
                            "was withdrawn (tvalid fell)"
                            if beat is None
                            else f"changed to tdata 0x{int(beat[0], 2):x}, tlast {beat[1]}, "
                            f"tuser {beat[2]}"
                        )
                        + " before tready"
                    )
                else:
                    self.held += 1
            hold = None
            if rst != "1":
                continue
            if bits(s_valid) == "1":
                if bits(s_ready) == "1":
                    self.in_beats += 1
                    if self.first_in is None:
                        self.first_in = cycle
                else:
                    self.in_stalls += 1
            if beat is None:
                continue
            if ready == "1":
                self.last_out = cycle
                self.sb.beat(cycle, int(beat[0], 2), int(beat[1], 2), int(beat[2], 2))
            else:
                self.stalls += 1
                hold, hold_cycle = beat, cycle

    def restart_timing(self) -> None:
        self.first_in = self.last_out = None


def pauses(rng: random.Random, probability: float, burst: int = 1):
    """An endless pause pattern: each step paused with ``probability``, in runs of 1..burst
    clocks (long runs fill the core's FIFO and stall its input)."""
    while True:
        paused = rng.random() < probability
        for _ in range(rng.randint(1, burst)):
            yield paused
