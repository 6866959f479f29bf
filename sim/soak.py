# SPDX-License-Identifier: Apache-2.0
"""Constrained-random soak: random strobes, start timing and resets, every output every cycle.

``stimulus(cfg, cycles, seed)`` draws what a careless host could do to a unit, cycle by cycle
(sim/soak_stimulus.py): each write strobe and ``start`` at random, operand values from the
extremes, values next to 0 (so a register crosses 0 from one job to the next, e.g. the
divider's k), powers of two and uniform ones, writes in the start cycle and in every busy cycle,
and a short random reset now and then.  The protocol model (sim/protocol.py) predicts every
output in every cycle: ``predict`` steps ``ProtocolModel``, the readable reference; the soak
itself takes the same prediction, and the vector file, from numba kernels over the stimulus
arrays (sim/soak_predict.py, sim/soak_file.py: millions of cycles a second, equal to
``predict`` and ``write_vectors`` cycle by cycle and byte by byte, tests/test_soak_fast.py).

``run_soak(cfg, cycles, seed)`` writes the stimulus and the predictions as a binary vector file
(one record per cycle: stimulus, then expected outputs and their mask for RESET_ALL = 0, then
for RESET_ALL = 1; ``write_vectors``, read by ``$fread`` in sim/vectors/vector_loop.vh) and
replays it through the unit in a plain Verilog bench (sim/vectors/tb_<unit>.v, no Python in the
loop; one instance with RESET_ALL = 0 and one with RESET_ALL = 1), which compares every output
of each instance with that instance's prediction in every cycle: the RESET_ALL = 1 instance
is held to its own reset rule (its data outputs read 0 from a reset to the next result, where
RESET_ALL = 0 leaves them undefined).  A soak longer than ``SEGMENT`` cycles runs as segments
of its own stimulus (each from a reset, segment i drawn from the seed and i), one vector file
and one replay at a time, so its length is bounded by time only.  The same file, for a fixed
seed, is each committed vector set under sim/vectors/<set>/ (its ``vectors.bin``;
sim/vector_sets.py, ``make vectors``).  Each mismatch comes back decoded: the cycle, the output,
the value, the model's value, and the operands of the job that reproduce it, with the seed
that replays the whole run (``SOAK_SEED``).  The cocotb benches drive the same stimulus through
their monitor.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass, field, fields
from importlib.resources import files
from pathlib import Path

from sim import soak_file, soak_predict, soak_stimulus, units, vector_run
from sim.protocol import Job, Port, ProtocolModel, Stats, UnitSpec, from_field, to_field

SIM_DIR = Path(__file__).resolve().parent
VECTOR_DIR = SIM_DIR / "vectors"
RTL_DIR = Path(str(files("model.rtl")))
# Cycles per vector file of a long soak: a segment's file and arrays stay a few tens of MB.
SEGMENT = 1_000_000

Inputs = dict[str, int]


def stimulus(cfg: units.UnitConfig, cycles: int, seed: int) -> list[Inputs]:
    """``cycles`` edges of random inputs (sim/soak_stimulus.py); the first three hold reset
    (the unit starts known)."""
    return soak_stimulus.stimulus(cfg, cycles, seed).as_inputs()


@dataclass
class Prediction:
    outputs: list[dict[str, int | None]]
    jobs: list[Job | None]  # the latest job at each cycle, for reports
    result_jobs: list[Job | None]  # the job whose result the held outputs show
    stats: Stats

    def job_at(self, cycle: int) -> Job | None:
        return self.jobs[cycle]

    def result_job_at(self, cycle: int) -> Job | None:
        return self.result_jobs[cycle]


def predict(cfg: units.UnitConfig, stim: list[Inputs], reset_all: bool = False) -> Prediction:
    """``ProtocolModel`` stepped over ``stim``, for an RTL built with RESET_ALL = ``reset_all``."""
    model = ProtocolModel(units.spec(cfg), units.expect(cfg), reset_all)
    outputs, jobs, result_jobs = [], [], []
    for inputs in stim:
        outputs.append(model.step(inputs))
        jobs.append(model.last_job)
        result_jobs.append(model.result_job)
    return Prediction(outputs, jobs, result_jobs, model.stats)


# ---------------------------------------------------------------------- vector files
def stim_fields(spec: UnitSpec) -> list[tuple[str, Port]]:
    """The stimulus word, MSB first: rst_n, start, then per operand its strobe and its value."""
    fields = [("rst_n", Port("rst_n", 1)), ("start", Port("start", 1))]
    for p in spec.operands:
        fields += [(f"{p.name}_we", Port(f"{p.name}_we", 1)), (f"{p.name}_in", p)]
    return fields


def out_fields(spec: UnitSpec) -> list[tuple[str, Port]]:
    """The response word, MSB first: busy, valid, then every output."""
    return [("busy", Port("busy", 1)), ("valid", Port("valid", 1))] + [
        (p.name, p) for p in spec.outputs
    ]


def pack(fields: list[tuple[str, Port]], values: dict[str, int | None]) -> tuple[int, int]:
    """(word, care mask) of ``values``; a ``None`` value is a don't-care field."""
    word = mask = 0
    for name, port in fields:
        word <<= port.width
        mask <<= port.width
        value = values.get(name)
        if value is not None:
            word |= to_field(value, port)
            mask |= (1 << port.width) - 1
    return word, mask


def unpack(fields: list[tuple[str, Port]], word: int) -> dict[str, int]:
    values = {}
    for name, port in reversed(fields):
        values[name] = from_field(word & ((1 << port.width) - 1), port)
        word >>= port.width
    return values


def width(fields: list[tuple[str, Port]]) -> int:
    return sum(port.width for _, port in fields)


Layout = list[tuple[str, int, int, int]]  # per field: name, shift, lowest legal value, bits


def _layout(fields: list[tuple[str, Port]]) -> Layout:
    out, shift = [], width(fields)
    for name, port in fields:
        shift -= port.width
        lo = -(1 << (port.width - 1)) if port.signed else 0
        out.append((name, shift, lo, port.width))
    return out


def _pack_fast(layout: Layout, values: dict[str, int | None]) -> tuple[int, int]:
    """``pack`` with the layout worked out once (the same words, the same range check)."""
    word = mask = 0
    for name, shift, lo, bits in layout:
        value = values.get(name)
        if value is not None:
            if not lo <= value < (1 << bits):
                raise ValueError(f"{name} = {value} does not fit in {bits} bits")
            word |= (value & ((1 << bits) - 1)) << shift
            mask |= ((1 << bits) - 1) << shift
    return word, mask


def record_bytes(spec: UnitSpec) -> tuple[int, int]:
    """(stimulus bytes, bytes of one instance's {mask, expect}) of a record of the binary
    vector file; a record is the stimulus, then the RESET_ALL = 0 pair, then the RESET_ALL = 1
    pair (``record_size``)."""
    return -(-width(stim_fields(spec)) // 8), -(-2 * width(out_fields(spec)) // 8)


def record_size(spec: UnitSpec) -> int:
    """Bytes of one record: the stimulus word and both instances' {mask, expect}."""
    sb, ob = record_bytes(spec)
    return sb + 2 * ob


def write_vectors(
    spec: UnitSpec,
    stim: list[Inputs],
    expected: list[dict[str, int | None]],
    path: Path,
    expected_reset_all: list[dict[str, int | None]],
) -> Path:
    """The binary vector file (sim/vectors/vector_loop.vh) at ``path``: per cycle the stimulus
    word, then ``{mask, expect}`` of ``expected`` (the RESET_ALL = 0 instance's prediction),
    then of ``expected_reset_all`` (the RESET_ALL = 1 instance's), each big-endian in whole
    bytes; returns ``path``."""
    path.parent.mkdir(parents=True, exist_ok=True)
    sf, of = stim_fields(spec), out_fields(spec)
    sb, ob = record_bytes(spec)
    ow = width(of)
    stim_layout, out_layout = _layout(sf), _layout(of)
    # Many cycles repeat an earlier one (held inputs, a busy unit): each distinct stimulus and
    # each distinct prediction is packed once.
    stims: dict[tuple, bytes] = {}
    pairs: dict[tuple, bytes] = {}
    records = bytearray()
    for inputs, *outputs in zip(stim, expected, expected_reset_all, strict=True):
        key = tuple(inputs.items())
        record = stims.get(key)
        if record is None:
            record = stims[key] = _pack_fast(stim_layout, inputs)[0].to_bytes(sb, "big")
        records += record
        for out in outputs:
            key = tuple(out.items())
            pair = pairs.get(key)
            if pair is None:
                word, mask = _pack_fast(out_layout, out)
                pair = pairs[key] = ((mask << ow) | word).to_bytes(ob, "big")
            records += pair
    path.write_bytes(bytes(records))
    return path


def read_vectors(spec: UnitSpec, path: Path) -> list[tuple[int, int, int, int, int]]:
    """(stimulus, expect, mask, expect with RESET_ALL = 1, its mask) words of every record of a
    vector file (tests, reports)."""
    sb, ob = record_bytes(spec)
    ow = width(out_fields(spec))
    size = sb + 2 * ob
    data = path.read_bytes()
    if len(data) % size:
        raise ValueError(f"{path}: {len(data)} bytes is not a whole number of {size}-byte records")
    out = []
    for at in range(0, len(data), size):
        stim = int.from_bytes(data[at : at + sb], "big")
        pair0 = int.from_bytes(data[at + sb : at + sb + ob], "big")
        pair1 = int.from_bytes(data[at + sb + ob : at + size], "big")
        low = (1 << ow) - 1
        out.append((stim, pair0 & low, pair0 >> ow, pair1 & low, pair1 >> ow))
    return out


# ---------------------------------------------------------------------- the Verilog replay
@dataclass
class SoakResult:
    unit: str
    seed: int
    cycles: int
    stats: Stats
    mismatches: list[str] = field(default_factory=list)
    mismatch_count: int = 0
    log: str = ""
    # seconds per step: stimulus, predict, write (CPU), build, replay (wall), replay_cpu
    seconds: dict[str, float] = field(default_factory=dict)

    def summary(self) -> str:
        s = self.stats
        return (
            f"{self.unit} soak, seed {self.seed}: {self.cycles} cycles, every output checked in "
            f"each; {s.results_compared} results in {s.jobs_completed} jobs, {s.jobs_aborted} "
            f"aborted by {s.resets} reset cycles, {s.writes_ignored} writes and "
            f"{s.starts_ignored} starts while busy, {s.writes_at_start} starts with a write, "
            f"{s.back_to_back} back-to-back; {self.mismatch_count} mismatches"
        )


# The bench's lines (sim/vectors/vector_loop.vh): one per mismatch, then the count.
MISMATCH = re.compile(
    r"^MISMATCH cycle (\d+) RESET_ALL=(\d) "
    r"got ([0-9a-fxz]+) expected ([0-9a-f]+) mask ([0-9a-f]+)$",
    re.I | re.M,
)
DONE = vector_run.DONE


def verilog_parameters(params: dict[str, object]) -> dict[str, str]:
    """NAME -> Verilog value text: strings and paths in double quotes, the rest integers."""
    return {
        key: f'"{value}"' if isinstance(value, str | Path) else str(int(value))  # type: ignore[call-overload]
        for key, value in params.items()
    }


def write_segment(
    cfg: units.UnitConfig, cycles: int, seed: int, segment: int, path: Path
) -> tuple[soak_stimulus.Stimulus, soak_predict.Prediction, dict[str, float]]:
    """Segment ``segment`` of a soak: ``cycles`` cycles of stimulus, their prediction and the
    vector file at ``path``; with the CPU seconds of each step (stimulus, predict, write)."""
    t0 = time.process_time()
    stim = soak_stimulus.stimulus(cfg, cycles, seed, segment)
    t1 = time.process_time()
    pred = soak_predict.predict(cfg, stim)
    t2 = time.process_time()
    path.parent.mkdir(parents=True, exist_ok=True)
    soak_file.write_vector_file(cfg, stim, pred, path)
    steps = {"stimulus": t1 - t0, "predict": t2 - t1, "write": time.process_time() - t2}
    return stim, pred, steps


def run_soak(
    cfg: units.UnitConfig,
    cycles: int,
    seed: int,
    build_dir: Path,
    parameters: dict[str, object],
    rtl: Path | None = None,
    sim: str = "icarus",
    build_root: Path | None = None,
    segment: int = SEGMENT,
) -> SoakResult:
    """Replay ``cycles`` random cycles through the RTL under ``sim`` (Icarus by default, or
    ``verilator``); decode every mismatch.  ``result.seconds`` times each step (summed over the
    segments).

    ``parameters`` are the unit's Verilog parameters (sim.runner.hdl_parameters); ``rtl``
    replaces ``rtl/<unit>.v`` (a saved mutant, to show the soak can fail).  The bench is built
    under ``build_root`` (default ``build_dir``; a build of the same configuration there is
    reused, sim/vector_run.py).  More than ``segment`` cycles run as segments of at most that
    many (each starting with a reset); the first segment with a mismatch ends the soak.
    """
    spec = units.spec(cfg)
    top = f"tb_{spec.toplevel}"
    built = vector_run.build(
        spec.toplevel, verilog_parameters(parameters), sim, build_root or build_dir, rtl
    )
    if not built.ok:
        raise RuntimeError(f"{sim} could not build {top}:\n{built.log}")
    seconds = dict.fromkeys(("stimulus", "predict", "write", "replay", "replay_cpu"), 0.0)
    seconds["build"] = built.seconds
    result = SoakResult(spec.toplevel, seed, 0, Stats(), seconds=seconds)
    vectors = build_dir / "vectors.bin"
    for index, first in enumerate(range(0, cycles, segment)):
        n = min(segment, cycles - first)
        stim, pred, steps = write_segment(cfg, n, seed, index, vectors)
        for key, value in steps.items():
            seconds[key] += value
        ran = vector_run.run(built, vectors, n, timeout=1800)
        seconds["replay"] += ran.wall_s
        seconds["replay_cpu"] += ran.cpu_s
        done = DONE.search(ran.log)
        # The bench ends with a non-zero exit status after its count when anything mismatched.
        failed_clean = done is not None and int(done.group(2)) > 0
        if (ran.returncode != 0 and not failed_clean) or done is None or int(done.group(1)) != n:
            raise RuntimeError(
                f"{top} did not finish its {n} cycles (exit {ran.returncode}):\n{ran.log}"
            )
        result.cycles += n
        for f in fields(Stats):
            if f.name != "errors":
                setattr(
                    result.stats,
                    f.name,
                    getattr(result.stats, f.name) + getattr(pred.stats, f.name),
                )
        result.log = ran.log
        result.mismatch_count += int(done.group(2))
        of = out_fields(spec)
        for m in MISMATCH.finditer(ran.log):
            text = _describe(spec, of, int(m.group(1)), m.groups()[2:], pred, stim, first)
            result.mismatches.append(f"RESET_ALL = {m.group(2)}, {text}")
        if result.mismatch_count:
            break
    return result


def _describe(
    spec: UnitSpec,
    of: list[tuple[str, Port]],
    cycle: int,
    words: tuple[str, str, str],
    pred: Prediction | soak_predict.Prediction,
    stim: soak_stimulus.Stimulus,
    first: int = 0,
) -> str:
    """One mismatch of ``cycle`` (of a segment starting at cycle ``first``) as text."""
    got_text, want_text, mask_text = words
    want, mask = int(want_text, 16), int(mask_text, 16)
    expected = unpack(of, want)
    care = unpack([(n, Port(n, p.width)) for n, p in of], mask)
    if re.search(r"[xz]", got_text, re.I):
        got = {"(X/Z in the response word)": got_text}
        bad = [n for n in care if care[n]]
    else:
        got = unpack(of, int(got_text, 16))
        bad = [n for n in care if care[n] and got[n] != expected[n]]
    held = {p.name for p in spec.outputs if p.kind != "strobe"}
    between = not expected["valid"] and set(bad) <= held
    job = pred.result_job_at(cycle) if between else pred.job_at(cycle)
    which = "the result held from job" if between else "job"
    diffs = "; ".join(f"{n} = {got.get(n, '?')}, expected {expected[n]}" for n in bad)
    return (
        f"cycle {first + cycle}: {diffs} (valid expected {expected['valid']}); {which} "
        f"{_job_text(job, first)}; inputs at this edge {stim.inputs(cycle)}"
    )


def _job_text(job: Job | None, first: int = 0) -> str:
    if job is None:
        return "none since reset"
    ops = ", ".join(f"{k}={v}" for k, v in job.operands.items())
    write = ", with an operand write in the start cycle" if job.write_at_start else ""
    return f"with inputs {ops} (started at cycle {first + job.started_at - 1}{write})"
