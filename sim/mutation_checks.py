# SPDX-License-Identifier: Apache-2.0
"""The checks a mutant of ``make mutants`` meets (sim/mutation.py), in order, and one run of
one: a unit's committed vector set, then soaks of the same configuration with other seeds; the
core's committed set as the FuseSoC sim target runs it, then at full rate, with other idles
and stalls, and random spans; the directed runs and the highlight lines, then the BRDF unit's
own checks (sim/mutation_brdf.py), and the core's rounding, sparse, epicentre and saturation
spans, last.  A check's files (a soak, the random spans) are written when a mutant first
reaches it, afresh: the generators and the model may change.

Size: about 700 lines: every check is a generator of stimulus aimed at one kind of fault,
and the list's order is the record's (a check added goes last), so they stay together; the
BRDF unit's, over its own model of words and marks, are a module of their own.
"""

from __future__ import annotations

import functools
import math
import random
import re
import subprocess
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from model.render import core
from model.render.pipeline import METHODS
from model.units import brdf
from model.units.brdf import FixedConfig
from model.units.specular import SpecularConfig
from sim import core_run, soak_file, soak_predict, soak_stimulus, units, vector_run, vector_sets
from sim.mutation_brdf import (
    BRDF_EXHAUSTIVE,
    BRDF_FAR,
    BRDF_HIGHLIGHT,
    BRDF_PIXEL_SAMPLE,
    EXHAUSTIVE_PIXELS,
    PIXEL_REST_PARTS,
    brdf_exhaustive_stimulus,
    brdf_far_inputs,
    brdf_highlight_inputs,
    brdf_pixel_rest,
    brdf_pixel_rest_stimulus,
    brdf_pixel_sample_stimulus,
)
from sim.protocol import UnitSpec

SIM = "verilator"
# the netlist's mutation select input
CTRL = "mutsel"
# The core's committed set is written for the pipeline configuration of method (h): both paths.
CORE_CONFIG = METHODS["diffuse"]

# The stronger checks a mutant meets after its committed set: (name, seed, cycles) of a soak of
# the unit's default configuration; for the core (name, spans, idle %, stall %, seed).
UNIT_SOAKS: tuple[tuple[str, int, int], ...] = (
    ("soak seed 1, 100k cycles", 1, 100_000),
    ("soak seed 2, 100k cycles", 2, 100_000),
)
# After the directed run, for the few it leaves alive: a long soak (the golden model's soak path
# writes millions of cycles a second, the replay runs as fast)
LONG_SOAKS: tuple[tuple[str, int, int], ...] = (("soak seed 3, 4M cycles", 3, 4_000_000),)
CORE_RUNS: tuple[tuple[str, str, int, int, int], ...] = (
    # the FuseSoC sim target's run of the committed set comes first (the design's vector set)
    ("core_default at full rate", "committed", 0, 0, 1),
    ("core_default, 50 % idles and stalls, seed 7", "committed", 50, 50, 7),
)
# Random spans: (name, spans, longest random length, every how many the longest of all, the
# spans' seed, idle %, stall %, the bench's seed)
CORE_RANDOM_RUNS: tuple[tuple[str, int, int, int, int, int, int, int], ...] = (
    ("2000 random spans, 1 to 40 and 2047 pixels, 20 % idles, 30 % stalls",
     2000, 40, 400, 11, 20, 30, 3),
    ("20000 random spans, 1 to 200 and 2047 pixels, 10 % idles, 10 % stalls",
     20000, 200, 1000, 13, 10, 10, 5),
)  # fmt: skip


@dataclass(frozen=True)
class Check:
    """One check a mutant meets: a vector file of the unit's bench, or a run of the core's."""

    name: str
    vector_file: Path | None = None  # units
    cycles: int = 0  # 0: as many as the vector file has records (``spec`` gives their size)
    spans: Path | None = None  # the core
    expect: Path | None = None
    n_spans: int = 0
    n_pixels: int = 0
    idle_pct: int = 0
    stall_pct: int = 0
    seed: int = 1
    # writes the check's files (a soak, random spans) when a mutant first reaches the check
    writer: Callable[[], None] | None = field(default=None, compare=False, repr=False)
    spec: UnitSpec | None = field(default=None, compare=False, repr=False)

    def records(self) -> int:
        """The cycles to replay: ``cycles``, or the vector file's records."""
        if self.cycles or self.vector_file is None or self.spec is None:
            return self.cycles
        _, _, stim_bytes, pair_bytes = soak_file.record_layout(self.spec)
        return self.vector_file.stat().st_size // (stim_bytes + 2 * pair_bytes)


@dataclass(frozen=True)
class Bench:
    """The built bench: the command (without plusargs), its folder, the build's seconds."""

    command: tuple[str, ...]
    folder: Path
    seconds: float


def _soak_check(cfg: units.UnitConfig, name: str, seed: int, cycles: int, folder: Path) -> Check:
    """A soak of ``cycles`` cycles with ``seed``, written afresh on first use (the generator
    may change)."""
    soak_dir = folder / "checks" / f"soak_{seed}_{cycles}"

    def write() -> None:
        soak_dir.mkdir(parents=True, exist_ok=True)
        vector_sets.write_stimulus(cfg, cycles, seed, soak_dir)

    return Check(name, soak_dir / "vectors.bin", cycles, writer=write)


def _inputs_check(
    cfg: units.UnitConfig, name: str, rows: Callable[[units.UnitConfig], list[dict[str, int]]],
    folder: Path,
) -> Check:  # fmt: skip
    """The rows ``rows(cfg)`` gives, with the golden model's prediction, written on first use;
    its length is known once written (the file's records)."""
    out = folder / "checks" / name.split(":")[0].replace(" ", "_") / "vectors.bin"

    def write() -> None:
        out.parent.mkdir(parents=True, exist_ok=True)
        stim = soak_stimulus.from_inputs(units.spec(cfg), rows(cfg))
        soak_file.write_vector_file(cfg, stim, soak_predict.predict(cfg, stim), out)

    return Check(name, out, 0, writer=write, spec=units.spec(cfg))


def _stimulus_check(
    cfg: units.UnitConfig, name: str,
    stimulus: Callable[[units.UnitConfig], soak_stimulus.Stimulus], folder: Path,
) -> Check:  # fmt: skip
    """As ``_inputs_check``, the stimulus built whole (``stimulus(cfg)``: millions of cycles)."""
    out = folder / "checks" / name.split(":")[0].replace(" ", "_") / "vectors.bin"

    def write() -> None:
        out.parent.mkdir(parents=True, exist_ok=True)
        stim = stimulus(cfg)
        soak_file.write_vector_file(cfg, stim, soak_predict.predict(cfg, stim), out)

    return Check(name, out, 0, writer=write, spec=units.spec(cfg))


def _pixel_checks(cfg: FixedConfig, folder: Path) -> list[Check]:
    """The one-pixel lines of a BRDF form whose exhaustive check has the top C's lines alone:
    for the sample's 64 n, then for the other n in ``PIXEL_REST_PARTS`` parts."""
    rest = [
        _stimulus_check(cfg, brdf_pixel_rest(part)[0], brdf_pixel_rest_stimulus(part), folder)
        for part in range(PIXEL_REST_PARTS)
    ]
    return [_stimulus_check(cfg, BRDF_PIXEL_SAMPLE, brdf_pixel_sample_stimulus, folder), *rest]


def unit_checks(vector_set: str, folder: Path) -> list[Check]:
    """The committed set, then the longer soaks of the same configuration, the directed run,
    the operand bits and the long soak (each written on first use into ``folder``)."""
    set_dir = vector_run.VECTOR_DIR / vector_set
    _, params = vector_sets.set_parameters(set_dir)
    cfg = vector_sets.SETS[vector_set][0]
    return [
        Check(vector_set, set_dir / "vectors.bin", int(params["CYCLES"])),
        *(_soak_check(cfg, name, seed, cycles, folder) for name, seed, cycles in UNIT_SOAKS),
        _inputs_check(cfg, DIRECTED, directed_inputs, folder),
        _inputs_check(cfg, OPERAND_BITS, operand_bit_inputs, folder),
        *(_soak_check(cfg, name, seed, cycles, folder) for name, seed, cycles in LONG_SOAKS),
        *(
            [_inputs_check(cfg, HIGHLIGHT, highlight_inputs, folder)]
            if isinstance(cfg, SpecularConfig)
            else []
        ),
        *(
            [
                _inputs_check(cfg, BRDF_HIGHLIGHT, brdf_highlight_inputs, folder),
                _inputs_check(cfg, BRDF_FAR, brdf_far_inputs, folder),
                _stimulus_check(cfg, BRDF_EXHAUSTIVE, brdf_exhaustive_stimulus, folder),
                *(_pixel_checks(cfg, folder) if cfg.form not in EXHAUSTIVE_PIXELS else []),
            ]
            if isinstance(cfg, FixedConfig)
            else []
        ),
    ]


DIRECTED = "directed: each operand at 0, 1, the powers of two and their neighbours, its ends"
DIRECTED_SEED = 5
OPERAND_BITS = (
    "operand bits: for each bit of each operand, a job whose results that bit changes, and the "
    "job with the bit flipped, each written two cycles before its start"
)
# Random jobs tried per operand bit before the bit is given up as one no result shows
BIT_TRIES = 2500


def corners(lo: int, hi: int, width: int) -> list[int]:
    """0, 1, every power of two and its neighbours, of either sign, and both ends, in lo..hi."""
    values = {0, 1, lo, lo + 1, hi, hi - 1}
    for k in range(width + 1):
        for v in ((1 << k) - 1, 1 << k, (1 << k) + 1):
            values.update((v, -v))
    return sorted(v for v in values if lo <= v <= hi)


def directed_inputs(cfg: units.UnitConfig) -> list[dict[str, int]]:
    """Reset, then one job per corner value of each operand (``corners``; every n of the
    specular unit), the other operands random (short lines), each written, started and
    waited for, every other one followed by a reset cycle."""
    spec = units.spec(cfg)
    ops = spec.operands
    rng = random.Random(DIRECTED_SEED)
    ranges = {p.name: soak_stimulus.port_range(p) for p in ops}
    idle = {"rst_n": 1, "start": 0}
    rows: list[dict[str, int]] = []
    held = {p.name: 0 for p in ops}

    def row(base: dict[str, int], we: int) -> dict[str, int]:
        out = dict(base)
        for p in ops:
            out[f"{p.name}_we"] = we
            out[f"{p.name}_in"] = held[p.name]
        return out

    rows += [row({"rst_n": 0, "start": 0}, 0)] * 3
    for p in ops:
        values = corners(*ranges[p.name], p.width)
        if p.name == "n":
            values = list(range(ranges["n"][0], ranges["n"][1] + 1))
        for index, v in enumerate(values):
            for q in ops:
                lo, hi = ranges[q.name]
                held[q.name] = (
                    v if q is p else rng.randint(lo, min(hi, 40) if q.name == "len" else hi)
                )
            rows.append(row(idle, 1))
            rows.append(row({"rst_n": 1, "start": 1}, 0))
            length = held.get("len", 0)
            wait = {
                "divider_shift": 24,
                "gouraud_segment": length // max(getattr(cfg, "p", 1), 1) + 4,
                # the BRDF unit's latency is the form's (up to 32 clocks): the line's last pixel
                "brdf_unit": length + brdf.fill_latency(cfg) + 4
                if isinstance(cfg, FixedConfig)
                else 0,
            }
            rows += [row(idle, 0)] * wait.get(spec.toplevel, length + 24)
            if index % 2 == 0:  # a reset after every other job, its flags still up
                rows.append(row({"rst_n": 0, "start": 0}, 0))
    return rows


HIGHLIGHT = (
    "highlight lines: every pixel inside the highlight of its n, C in its top quarter, "
    "each line sweeping a few ROM-12 addresses"
)
HIGHLIGHT_JOBS = 1500


def highlight_inputs(cfg: units.UnitConfig) -> list[dict[str, int]]:
    """Reset, then ``HIGHLIGHT_JOBS`` lines of the specular unit that stay where cos^n is
    above 1/256 (n random in 1..1000, z0 within that angle, dz so small that the line stays
    there), C in the top quarter of its range: every pixel reads a non-zero ROM-12 word and a
    change of one address or one word is likely to change a result.  A random soak's lines
    leave the highlight within a few pixels, so it meets a rounding boundary of the angle
    rarely; these meet one every few hundred pixels.  Each job is written, started and waited
    for."""
    spec = units.spec(cfg)
    ranges = {p.name: soak_stimulus.port_range(p) for p in spec.operands}
    rng = random.Random(DIRECTED_SEED + 2)
    zf = cfg.z_frac_bits
    c_lo, c_hi = ranges["c"]
    len_hi = ranges["len"][1]

    def jobs() -> Iterator[dict[str, int]]:
        for _ in range(HIGHLIGHT_JOBS):
            n = rng.randint(1, 1000)
            # the angle where cos^n falls to 1/256, in the angle register's LSBs (units of pi/2)
            edge = int(math.acos(2.0 ** (-8.0 / n)) / (math.pi / 2) * (1 << zf))
            length = rng.randint(1, len_hi)
            z0 = rng.randint(-edge, edge)
            step = max(1, (edge - abs(z0)) // length)
            yield dict(
                c=rng.randint(c_hi - (c_hi - c_lo) // 4, c_hi), n=n, len=length, z0=z0,
                dz=rng.randint(-step, step),
            )  # fmt: skip

    return soak_stimulus.line_rows(spec, jobs(), lambda job: job["len"] + 24)


def operand_bit_jobs(
    cfg: units.UnitConfig,
) -> list[tuple[str, int, dict[str, int], dict[str, int]]]:
    """For each bit b of each operand: (operand, b, a job, the job with bit b of that operand
    flipped), the job found at random (the golden model judges ``BIT_TRIES`` of them at most,
    lines of any length) such that the two give different results; a bit no tried job shows
    (a z0 bit below what the angle's rounding keeps, a flip that leaves the operand's range)
    has none."""
    spec = units.spec(cfg)
    ops = spec.operands
    expect = units.expect(cfg)
    rng = random.Random(DIRECTED_SEED + 1)
    ranges = {p.name: soak_stimulus.port_range(p) for p in ops}
    found = []
    for p in ops:
        lo, hi = ranges[p.name]
        for b in range(p.width):
            for _ in range(BIT_TRIES):
                job = {q.name: rng.randint(*ranges[q.name]) for q in ops}
                flipped = (job[p.name] ^ (1 << b)) & ((1 << p.width) - 1)  # two's complement
                if p.signed and flipped >= 1 << (p.width - 1):
                    flipped -= 1 << p.width
                if not lo <= flipped <= hi:
                    continue
                other = {**job, p.name: flipped}
                if expect(job).results != expect(other).results:
                    found.append((p.name, b, job, other))
                    break
    return found


def operand_bit_inputs(cfg: units.UnitConfig) -> list[dict[str, int]]:
    """Reset, then the jobs of ``operand_bit_jobs``, each pair's two jobs one after the other,
    so that each bit is 1 in one and 0 in the other.  Each job's operands are written, held
    for two idle cycles (what the registers' hold paths keep is what the job uses) and
    started; the next job waits for its results."""
    ops = units.spec(cfg).operands
    expect = units.expect(cfg)

    def row(values: dict[str, int], we: int, start: int, rst_n: int = 1) -> dict[str, int]:
        out = {"rst_n": rst_n, "start": start}
        for p in ops:
            out[f"{p.name}_we"] = we
            out[f"{p.name}_in"] = values[p.name]
        return out

    rows = [row({p.name: 0 for p in ops}, 0, 0, rst_n=0)] * 3
    for _, _, job, other in operand_bit_jobs(cfg):
        for values in (job, other):
            rows.append(row(values, 1, 0))
            rows += [row(values, 0, 0)] * 2
            rows.append(row(values, 0, 1))
            # to the job's last result, with room to spare
            rows += [row(values, 0, 0)] * (expect(values).busy_cycles + 4)
    return rows


def core_checks(folder: Path) -> list[Check]:
    """The committed set as the FuseSoC sim target runs it, then the stronger runs."""
    committed = vector_run.VECTOR_DIR / "core_default"
    spans, pixels = committed / "spans.hex", committed / "pixels.hex"
    n_spans = len(spans.read_text().split())
    n_pixels = pixels.read_text().count("\n")
    checks = [Check("core_default", None, 0, spans, pixels, n_spans, n_pixels, 20, 30, 1)]
    for name, which, idle, stall, seed in CORE_RUNS:
        if which == "committed":
            checks.append(Check(name, None, 0, spans, pixels, n_spans, n_pixels, idle, stall, seed))
    for name, count, longest, every, span_seed, idle, stall, seed in CORE_RANDOM_RUNS:
        rand_spans = folder / "checks" / f"spans_{span_seed}.hex"
        rand_pixels = folder / "checks" / f"pixels_{span_seed}.hex"

        def write(
            rand_spans: Path = rand_spans, rand_pixels: Path = rand_pixels, count: int = count,
            longest: int = longest, every: int = every, span_seed: int = span_seed,
        ) -> None:  # fmt: skip
            """``count`` spans of every length to ``longest`` pixels and every ``every``-th
            of the longest, every field random, and the model's pixel beats (afresh each
            run: the model may change)."""

            fmt = core.SpanFormat(CORE_CONFIG)
            rng = np.random.default_rng(span_seed)
            lengths = rng.integers(1, longest + 1, count)
            lengths[::every] = CORE_CONFIG.gouraud.len_max
            _write_span_files(core_run.random_spans(fmt, lengths, span_seed), rand_spans,
                              rand_pixels)  # fmt: skip

        checks.append(
            Check(name, None, 0, rand_spans, rand_pixels, count, 0, idle, stall, seed,
                  writer=write)
        )  # fmt: skip
    d_spans = folder / "checks" / "spans_directed.hex"
    d_pixels = folder / "checks" / "pixels_directed.hex"
    n_directed = len(directed_spans())
    checks.append(
        Check(CORE_DIRECTED, None, 0, d_spans, d_pixels, n_directed, 0, 10, 10, 9,
              writer=lambda: _write_span_files(list(directed_spans()), d_spans, d_pixels))
    )  # fmt: skip
    h_spans = folder / "checks" / "spans_highlight.hex"
    h_pixels = folder / "checks" / "pixels_highlight.hex"
    checks.append(
        Check(CORE_HIGHLIGHT, None, 0, h_spans, h_pixels, HIGHLIGHT_SPANS, 0, 10, 10, 9,
              writer=lambda: _write_span_files(highlight_spans(), h_spans, h_pixels))
    )  # fmt: skip
    r_spans = folder / "checks" / "spans_rounding.hex"
    r_pixels = folder / "checks" / "pixels_rounding.hex"
    checks.append(
        Check(CORE_ROUNDING, None, 0, r_spans, r_pixels, ROUNDING_SPANS, 0, 10, 10, 9,
              writer=lambda: _write_span_files(rounding_spans(), r_spans, r_pixels))
    )  # fmt: skip
    s_spans = folder / "checks" / "spans_sparse.hex"
    s_pixels = folder / "checks" / "pixels_sparse.hex"
    checks.append(
        Check(CORE_SPARSE, None, 0, s_spans, s_pixels, SPARSE_SPANS, 0, SPARSE_IDLE, 0, 9,
              writer=lambda: _write_span_files(sparse_spans(), s_spans, s_pixels))
    )  # fmt: skip
    t_spans = folder / "checks" / "spans_tables.hex"
    t_pixels = folder / "checks" / "pixels_tables.hex"
    checks.append(
        Check(CORE_TABLES, None, 0, t_spans, t_pixels, TABLE_SPANS, 0, 10, 10, 9,
              writer=lambda: _write_span_files(
                  highlight_spans(TABLE_SPANS, DIRECTED_SEED + 7, per_table=True), t_spans,
                  t_pixels))
    )  # fmt: skip
    u_spans = folder / "checks" / "spans_saturation.hex"
    u_pixels = folder / "checks" / "pixels_saturation.hex"
    checks.append(
        Check(CORE_SATURATION, None, 0, u_spans, u_pixels, SATURATION_SPANS, 0, 10, 10, 9,
              writer=lambda: _write_span_files(saturation_spans(), u_spans, u_pixels))
    )  # fmt: skip
    return checks


def _write_span_files(words: Sequence[int], spans: Path, pixels: Path) -> None:
    """The span beats ``words`` and the model's pixel beats, as the core's bench reads them."""
    fmt = core.SpanFormat(CORE_CONFIG)
    pix = core.PixelFormat(fmt.x_width, fmt.y_width)
    digits, pdigits = -(-fmt.width // 4), -(-pix.width // 4)
    spans.parent.mkdir(parents=True, exist_ok=True)
    spans.write_text("".join(f"{w:0{digits}x}\n" for w in words))
    pixels.write_text(
        "".join(
            f"{core.pixel_word(p, pix):0{pdigits}x} {p['last']:x} {p['n_err']:x}\n"
            for p in core.core_pixels(words, fmt)
        )
    )


CORE_DIRECTED = (
    "directed spans: each field at 0, 1, the powers of two and their neighbours, its ends, "
    "the others random, two spans a value"
)


@functools.cache
def directed_spans(seed: int = DIRECTED_SEED + 3) -> tuple[int, ...]:
    """The core's directed run, as ``directed_inputs`` is a unit's: for each field of the span
    beat (``corners`` of its range: z0 = -2.0, exactly -pi, is one), two spans of 1 to 40
    pixels with the field at that value and every other field random (n from 1 to 1000; the
    term the angle feeds switched on)."""

    fmt = core.SpanFormat(CORE_CONFIG)
    g, s = CORE_CONFIG.gouraud, CORE_CONFIG.specular
    z = (s.z_format.lo, s.z_format.hi, s.z_width)
    c = (0, (1 << s.c_width) - 1, s.c_width)
    i = (0, (1 << g.i_width) - 1, g.i_width)
    fields = {"z0": z, "dz": z, "diff_z0": z, "diff_dz": z, "c": c,
              "n": (0, (1 << core.N_WIDTH) - 1, core.N_WIDTH),
              "l": (0, g.len_max - 1, (g.len_max - 1).bit_length())}  # fmt: skip
    for ch in range(core.CHANNELS):
        fields.update({f"diff_c{ch}": c, f"i_start{ch}": i, f"i_end{ch}": i})
    rng = np.random.default_rng(seed)
    words = []
    for name, (lo, hi, width) in fields.items():
        for value in corners(lo, hi, width):
            for _ in range(2):
                lengths = [int(rng.integers(1, 41))]
                row = core.unpack(fmt.layout(), core_run.random_spans(fmt, lengths, int(
                    rng.integers(1 << 31)))[0])  # fmt: skip
                row["n"] = int(rng.integers(1, 1001))
                row[name] = value
                if name in ("z0", "dz"):
                    row["spec"] = 1
                if name in ("diff_z0", "diff_dz"):
                    row["diff"] = 1
                row["x"] = min(row["x"], (1 << fmt.x_width) - row["l"] - 1)
                words.append(core.pack(fmt.layout(), row))
    return tuple(words)


HIGHLIGHT_SPANS = 20_000
CORE_HIGHLIGHT = (
    f"{HIGHLIGHT_SPANS} highlight spans: 1 to 200 pixels inside the highlight of their n and "
    "within pi/2 of the diffuse angle, every C in the top quarter"
)


def _line(rng, edge: int, length: int) -> tuple[int, int]:
    """A line's start angle and step (random) that keep its ``length`` pixels within ``edge``
    of 0, drawn from ``rng`` in that order."""
    z0 = int(rng.integers(-edge, edge + 1))
    step = max(1, (edge - abs(z0)) // length)
    return z0, int(rng.integers(-step, step + 1))


def highlight_spans(
    count: int = HIGHLIGHT_SPANS, seed: int = DIRECTED_SEED + 4, per_table: bool = False
) -> list[int]:
    """The core's highlight lines (as ``highlight_inputs`` are the specular unit's): spans of
    1 to 200 pixels with both terms on, n random in 1..1000, the highlight angle and every
    pixel's where cos^n is above 1/256, the diffuse angle within pi/2, the highlight C and
    the three diffuse C in the top quarter of their range, the other fields random: a change
    of an angle below a ROM-12 address's rounding, or of a low bit of a table word, shows
    about once in 10^5 pixels, where random spans, mostly dark, show it almost never.
    ``per_table``: n drawn from a k range chosen at random first, so that each cos^k table
    (each ROM-12 bank) lights a quarter of the spans (n uniform in 1..1000 gives the k = 1, 2
    and 4 tables 1, 1 and 4 spans in 1000), and every angle within a quarter of the
    highlight's edge, its epicentre, where the table words are largest and a change of their
    low bit moves C x word across a rounding point most often."""

    fmt = core.SpanFormat(CORE_CONFIG)
    s = CORE_CONFIG.specular
    layout = fmt.layout()
    rng = np.random.default_rng(seed)
    c_hi = (1 << s.c_width) - 1
    right = 1 << s.z_frac_bits  # pi/2

    def top_quarter() -> int:
        return int(rng.integers(c_hi - c_hi // 4, c_hi + 1))

    words = []
    for _ in range(count):
        length = int(rng.integers(1, 201))
        row = core.unpack(layout, core_run.random_spans(fmt, [length], int(
            rng.integers(1 << 31)))[0])  # fmt: skip
        if per_table:
            lo, hi, _k = s.k_ranges[int(rng.integers(len(s.k_ranges)))]
            n = int(rng.integers(lo, hi + 1))
        else:
            n = int(rng.integers(1, 1001))
        edge = int(math.acos(2.0 ** (-8.0 / n)) / (math.pi / 2) * right)
        z0, dz = _line(rng, edge // 4 if per_table else edge, length)
        diff_z0, diff_dz = _line(rng, right - 1, length)
        row.update(n=n, spec=1, diff=1, z0=z0, dz=dz, diff_z0=diff_z0, diff_dz=diff_dz,
                   c=top_quarter())  # fmt: skip
        for ch in range(core.CHANNELS):
            row[f"diff_c{ch}"] = top_quarter()
        words.append(core.pack(layout, row))
    return words


ROUNDING_SPANS = 600
# How far from the rounding point of dI the quotients lie: each channel's a window, drawn
ROUNDING_WINDOWS = (8, 64, 512, 2048)
CORE_ROUNDING = (
    f"{ROUNDING_SPANS} rounding spans: 1024 to 2047 pixels, Gouraud only, each channel's "
    "quotient a x r within 8 to 2048 of a rounding point of its dI"
)


def rounding_spans(count: int = ROUNDING_SPANS, seed: int = DIRECTED_SEED + 5) -> list[int]:
    """The core's increment corners: spans of 1024 to 2047 pixels, the Gouraud term alone
    (spec = diff = 0), each channel's a = i_end - i_start chosen so that the divider's
    quotient a x r (r = round(2^N / l), the reciprocal ROM's word) lies within a window of
    8, 64, 512 or 2048 of a rounding point of dI = (q + 2^(N-1)) >> N, the other fields
    random.  A change of a low bit of a partial product or of the rounding constant moves
    dI by 1 LSB only there (a random a meets a window of 8 once in 2^16 quotients), and a
    long span shows that LSB: pixel x moves by x / 2^I_FRAC levels."""

    from model.units import divider

    fmt = core.SpanFormat(CORE_CONFIG)
    layout = fmt.layout()
    g, d = CORE_CONFIG.gouraud, CORE_CONFIG.divider
    n, top = d.recip_bits, (1 << g.i_width) - 1
    rng = np.random.default_rng(seed)
    words = []
    for _ in range(count):
        length = int(rng.integers(1024, g.len_max + 1))
        row = core.unpack(layout, core_run.random_spans(fmt, [length], int(
            rng.integers(1 << 31)))[0])  # fmt: skip
        row.update(spec=0, diff=0)
        intervals = row["l"]
        r = int(divider.reciprocal(intervals, n))
        zeros = (r & -r).bit_length() - 1  # a x r is a multiple of 2^zeros
        modulus = 1 << (n - zeros)
        inverse = pow(r >> zeros, -1, modulus)
        for ch in range(core.CHANNELS):
            window = int(rng.choice(ROUNDING_WINDOWS))
            target = ((1 << (n - 1)) + int(rng.integers(-window, window))) % (1 << n)
            a = ((target >> zeros) * inverse) % modulus
            # the a of that residue in -top..top, one drawn at random
            choices = list(range(a - (top // modulus + 1) * modulus, top + 1, modulus))
            a = int(rng.choice([v for v in choices if -top <= v]))
            start = int(rng.integers(max(0, -a), top - max(0, a) + 1))
            row[f"i_start{ch}"], row[f"i_end{ch}"] = start, start + a
        words.append(core.pack(layout, row))
    return words


SPARSE_SPANS = 400
# Input idles of the sparse run, %: a span beat every 50 cycles on average, longer than a
# pixel's way through the core, so the output FIFO runs empty between spans
SPARSE_IDLE = 98
CORE_SPARSE = (
    f"{SPARSE_SPANS} sparse spans: 1 to 8 pixels, {SPARSE_IDLE} % idles, no stalls (the "
    "output FIFO empties between spans)"
)


def sparse_spans(count: int = SPARSE_SPANS, seed: int = DIRECTED_SEED + 6) -> list[int]:
    """Short random spans (1 to 8 pixels, every field random) for a run with few span beats:
    the output FIFO empties after each span, at every fill of its pointers (the other runs
    keep it filling, so it empties only after their last pixel, which no bench sees past),
    and a pointer's wrap bit or an empty or full test that is wrong shows as a pixel beat too
    many or too few in mid-run."""

    fmt = core.SpanFormat(CORE_CONFIG)
    rng = np.random.default_rng(seed)
    return core_run.random_spans(fmt, rng.integers(1, 9, count), seed)


TABLE_SPANS = 8000
CORE_TABLES = (
    f"{TABLE_SPANS} epicentre spans, each cos^k table a quarter of them: as the highlight "
    "spans, n drawn from a k range chosen first, every angle within a quarter of the edge"
)

SATURATION_SPANS = 400
CORE_SATURATION = (
    f"{SATURATION_SPANS} saturation spans: the highlight alone (no diffuse term, Gouraud 0), C "
    "within 1/2 level of its top, every angle within a sixteenth of the highlight's edge"
)


def saturation_spans(count: int = SATURATION_SPANS, seed: int = DIRECTED_SEED + 8) -> list[int]:
    """The highlight unit's own saturation, seen at the core's output: spans of 1 to 64 pixels
    with the highlight term alone (diff = 0, every Gouraud start and end 0, so the sum is the
    highlight's word), C within half a level of its top (Q8.8: 255.5 and up) and every angle
    close to the epicentre, where C x the table word rounds to 256 and the highlight clamps to
    255.  Elsewhere the diffuse and Gouraud terms fill the sum, whose own saturation then
    hides what value the highlight clamped to."""

    fmt = core.SpanFormat(CORE_CONFIG)
    s = CORE_CONFIG.specular
    layout = fmt.layout()
    rng = np.random.default_rng(seed)
    c_hi = (1 << s.c_width) - 1
    right = 1 << s.z_frac_bits  # pi/2
    words = []
    for _ in range(count):
        length = int(rng.integers(1, 65))
        row = core.unpack(layout, core_run.random_spans(fmt, [length], int(
            rng.integers(1 << 31)))[0])  # fmt: skip
        n = int(rng.integers(1, 1001))
        edge = max(1, int(math.acos(2.0 ** (-8.0 / n)) / (math.pi / 2) * right) // 16)
        z0, dz = _line(rng, edge, length)
        row.update(n=n, spec=1, diff=0, z0=z0, dz=dz,
                   c=int(rng.integers(c_hi - (1 << (s.c_frac_bits - 1)), c_hi + 1)))  # fmt: skip
        for ch in range(core.CHANNELS):
            row[f"i_start{ch}"] = row[f"i_end{ch}"] = 0
        words.append(core.pack(layout, row))
    return words


def passes(bench: Bench, check: Check, mutant: int, work: Path) -> bool:
    """Mutant ``mutant`` passes ``check`` (no mismatch, the bench finished)."""
    if check.vector_file is not None:
        b = vector_run.Build(SIM, "", bench.folder, [*bench.command, f"+MUTANT={mutant}"], 0.0,
                             True, True, "")  # fmt: skip
        return vector_run.run(b, check.vector_file, check.records(), timeout=600).passed
    n_pixels = check.n_pixels or check.expect.read_text().count("\n")
    # the bench compares every beat with the model's itself: no beat file is written
    args = [
        f"+SPAN_FILE={check.spans}", f"+EXPECT_FILE={check.expect}", "+NO_OUT_FILE",
        f"+SPANS={check.n_spans}", f"+PIXELS={n_pixels}", f"+IDLE_PCT={check.idle_pct}",
        f"+STALL_PCT={check.stall_pct}", f"+SEED={check.seed}",
        f"+MAX_CYCLES={40 * n_pixels + 10000}", f"+MUTANT={mutant}", "+STOP_ON_ERROR=1",
    ]  # fmt: skip
    try:
        ran = subprocess.run([*bench.command, *args], capture_output=True, text=True,
                             cwd=bench.folder, timeout=600)  # fmt: skip
    except subprocess.TimeoutExpired:
        return False
    done = core_run.DONE.search(ran.stdout)
    return ran.returncode == 0 and done is not None and int(done.group(7)) == 0


# ---------------------------------------------------------------- the bench's wrapper
def parameter_names(abstract_il: str, top: str) -> list[str]:
    """The parameters of ``top`` as ``read_verilog -defer`` lists them (``write_rtlil``)."""
    body = abstract_il.split(f"module $abstract\\{top}\n", 1)[1].split("\nend\n", 1)[0]
    return re.findall(r"^\s*parameter \\(\w+)", body, re.M)


def ports(netlist_text: str, module: str) -> list[tuple[str, str]]:
    """(direction, declaration) of each port of ``module`` in a ``write_verilog`` netlist."""
    body = netlist_text.split(f"module {module}(", 1)[1].split("endmodule", 1)[0]
    found = re.findall(r"^\s*(input|output)\s+((?:\[\d+:\d+\]\s*)?\w+);", body, re.M)
    return [(d, decl) for d, decl in found]


def wrapper(top: str, params: list[str], port_list: list[tuple[str, str]], width: int) -> str:
    """A module ``top`` with the top's parameters and ports around ``<top>_mutants``, its
    ``mutsel`` from ``+MUTANT=<id>`` (0 without it)."""
    names = [decl.split()[-1] for _, decl in port_list if decl.split()[-1] != CTRL]
    lines = [
        "// Generated by sim/mutation.py: the top's parameters (unused: the netlist below is",
        "// built for the design's vector set) and ports around the netlist with every mutation,",
        f"// {CTRL} from +MUTANT=<id> (0: the original design).",
        f"module {top} #(",
        ",\n".join(f"    parameter {p} = 0" for p in params),
        f") ({', '.join(names)});",
    ]
    lines += [f"    {d} {decl};" for d, decl in port_list if decl.split()[-1] != CTRL]
    lines += [
        f"    reg [{width - 1}:0] {CTRL};",
        "    initial begin",
        f'        if (!$value$plusargs("MUTANT=%d", {CTRL})) {CTRL} = {width}\'d0;',
        "    end",
        f"    {top}_mutants mutants (",
        ",\n".join(f"        .{n}({n})" for n in [*names, CTRL]),
        "    );",
        "endmodule",
        "",
    ]
    return "\n".join(lines)
