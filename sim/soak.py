# SPDX-License-Identifier: Apache-2.0
"""Constrained-random soak: random strobes, start timing and resets, every output every cycle.

``stimulus(cfg, cycles, seed)`` draws what a careless host could do to a unit, cycle by cycle:
each write strobe and ``start`` at random, operand values from the extremes, values next to 0
(so a register crosses 0 from one job to the next, e.g. the divider's k), powers of two and
uniform ones, writes in the start cycle and in every busy cycle, and a short random reset now
and then.  The protocol model (sim/protocol.py) predicts every output in every cycle.

``run_soak(cfg, cycles, seed)`` writes the stimulus and the predictions as a binary vector file
(one record per cycle: stimulus, then expected outputs and their mask for RESET_ALL = 0, then
for RESET_ALL = 1; ``write_vectors``, read by ``$fread`` in sim/vectors/vector_loop.vh) and
replays it through the unit in a plain Verilog bench (sim/vectors/tb_<unit>.v, no Python in the
loop; one instance with RESET_ALL = 0 and one with RESET_ALL = 1), which compares every output
of each instance with that instance's prediction in every cycle: the RESET_ALL = 1 instance
is held to its own reset rule (its data outputs read 0 from a reset to the next result, where
RESET_ALL = 0 leaves them undefined).  The same
file, for a fixed seed, is each committed vector set under sim/vectors/<set>/ (its
``vectors.bin``; sim/vector_sets.py, ``make vectors``).  Each mismatch comes back decoded: the
cycle, the output, the value, the model's value, and the operands of the job that reproduce
it, with the seed that replays the whole run (``SOAK_SEED``).  The cocotb benches drive the
same stimulus through their monitor.
"""

from __future__ import annotations

import random
import re
import time
from dataclasses import dataclass, field
from importlib.resources import files
from pathlib import Path

from model.units.specular import N_MAX, SpecularConfig
from sim import units, vector_run
from sim.protocol import Job, Port, ProtocolModel, Stats, UnitSpec, from_field, to_field

SIM_DIR = Path(__file__).resolve().parent
VECTOR_DIR = SIM_DIR / "vectors"
RTL_DIR = Path(str(files("model.rtl")))

# Per cycle: chance of a reset (held 1..3 cycles), of start, of each write strobe.
P_RESET = 0.0015
P_START = 0.35
P_WRITE = 0.3
# Longest line the soak draws often (a long line now and then is drawn up to the maximum).
SHORT_LINE = 24
P_LONG_LINE = 0.02

Inputs = dict[str, int]


def extremes(port: Port) -> list[int]:
    """The operand values a soak favours: both ends, 0 and its neighbours, the ends' neighbours."""
    if port.signed:
        lo, hi = -(1 << (port.width - 1)), (1 << (port.width - 1)) - 1
    else:
        lo, hi = 0, (1 << port.width) - 1
    return sorted({v for v in (lo, lo + 1, -1, 0, 1, 2, hi - 1, hi) if lo <= v <= hi})


def _uniform(rng: random.Random, port: Port) -> int:
    if port.signed:
        return rng.randint(-(1 << (port.width - 1)), (1 << (port.width - 1)) - 1)
    return rng.randint(0, (1 << port.width) - 1)


def pick_value(rng: random.Random, port: Port, cfg: units.UnitConfig) -> int:
    """One operand value: extremes, near 0, a power of two (signed: either sign), or uniform."""
    if port.name == "len":
        hi = (1 << port.width) - 1
        if rng.random() < P_LONG_LINE:
            return rng.choice([hi, rng.randint(0, hi)])
        return rng.randint(0, SHORT_LINE)
    if port.name == "n" and isinstance(cfg, SpecularConfig):
        edges = {0, 1, N_MAX, N_MAX + 1, (1 << port.width) - 1}
        for hi in cfg.n_hi:
            edges.update((hi, hi + 1))
        if cfg.n_first > 1 or cfg.n_last < N_MAX:  # a kept range: its edges, and n inside it
            edges.update((cfg.n_first - 1, cfg.n_first, cfg.n_last, cfg.n_last + 1))
            if rng.random() < 0.3:
                return rng.randint(cfg.n_first, cfg.n_last)
        return rng.choice(sorted(edges)) if rng.random() < 0.5 else rng.randint(0, N_MAX + 23)
    r = rng.random()
    if r < 0.35:
        return rng.choice(extremes(port))
    if r < 0.55:
        return rng.randint(-2, 2) if port.signed else rng.randint(0, 2)
    if r < 0.7:
        value = 1 << rng.randrange(port.width - 1 if port.signed else port.width)
        return -value if port.signed and rng.random() < 0.5 else value
    return _uniform(rng, port)


def stimulus(cfg: units.UnitConfig, cycles: int, seed: int) -> list[Inputs]:
    """``cycles`` edges of random inputs; the first three hold reset (the unit starts known)."""
    spec = units.spec(cfg)
    rng = random.Random(f"soak-{spec.toplevel}-{seed}")
    held = {p.name: 0 for p in spec.operands}
    out: list[Inputs] = []
    reset_left = 3
    for _ in range(cycles):
        if reset_left == 0 and rng.random() < P_RESET:
            reset_left = rng.randint(1, 3)
        inputs: Inputs = {"rst_n": 0 if reset_left else 1, "start": int(rng.random() < P_START)}
        reset_left = max(0, reset_left - 1)
        for p in spec.operands:
            we = rng.random() < P_WRITE
            if we:
                held[p.name] = pick_value(rng, p, cfg)
            inputs[f"{p.name}_we"] = int(we)
            inputs[f"{p.name}_in"] = held[p.name]  # a port keeps its value when not written
        out.append(inputs)
    return out


@dataclass
class Prediction:
    outputs: list[dict[str, int | None]]
    jobs: list[Job | None]  # the latest job at each cycle, for reports
    result_jobs: list[Job | None]  # the job whose result the held outputs show
    stats: Stats


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


def run_soak(
    cfg: units.UnitConfig,
    cycles: int,
    seed: int,
    build_dir: Path,
    parameters: dict[str, object],
    rtl: Path | None = None,
    sim: str = "icarus",
    build_root: Path | None = None,
) -> SoakResult:
    """Replay ``cycles`` random cycles through the RTL under ``sim`` (Icarus by default, or
    ``verilator``); decode every mismatch.  ``result.seconds`` times each step.

    ``parameters`` are the unit's Verilog parameters (sim.runner.hdl_parameters); ``rtl``
    replaces ``rtl/<unit>.v`` (a saved mutant, to show the soak can fail).  The bench is built
    under ``build_root`` (default ``build_dir``; a build of the same configuration there is
    reused, sim/vector_run.py).
    """
    spec = units.spec(cfg)
    seconds = {}
    t0 = time.process_time()
    stim = stimulus(cfg, cycles, seed)
    t1 = time.process_time()
    pred = predict(cfg, stim)
    full = predict(cfg, stim, reset_all=True)
    t2 = time.process_time()
    vectors = write_vectors(spec, stim, pred.outputs, build_dir / "vectors.bin", full.outputs)
    seconds.update(stimulus=t1 - t0, predict=t2 - t1, write=time.process_time() - t2)
    top = f"tb_{spec.toplevel}"
    root = build_root or build_dir
    built = vector_run.build(spec.toplevel, verilog_parameters(parameters), sim, root, rtl)
    if not built.ok:
        raise RuntimeError(f"{sim} could not build {top}:\n{built.log}")
    ran = vector_run.run(built, vectors, cycles, timeout=1800)
    seconds.update(build=built.seconds, replay=ran.wall_s, replay_cpu=ran.cpu_s)
    log = ran.log
    done = DONE.search(log)
    # The bench ends with a non-zero exit status after its count when anything mismatched.
    failed_clean = done is not None and int(done.group(2)) > 0
    if (ran.returncode != 0 and not failed_clean) or done is None or int(done.group(1)) != cycles:
        raise RuntimeError(
            f"{top} did not finish its {cycles} cycles (exit {ran.returncode}):\n{log}"
        )
    result = SoakResult(spec.toplevel, seed, cycles, pred.stats, log=log, seconds=seconds)
    result.mismatch_count = int(done.group(2))
    of = out_fields(spec)
    for m in MISMATCH.finditer(log):
        cycle = int(m.group(1))
        text = _describe(spec, of, cycle, m.groups()[2:], pred, stim)
        result.mismatches.append(f"RESET_ALL = {m.group(2)}, {text}")
    return result


def _describe(
    spec: UnitSpec,
    of: list[tuple[str, Port]],
    cycle: int,
    words: tuple[str, str, str],
    pred: Prediction,
    stim: list[Inputs],
) -> str:
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
    job = pred.result_jobs[cycle] if between else pred.jobs[cycle]
    which = "the result held from job" if between else "job"
    diffs = "; ".join(f"{n} = {got.get(n, '?')}, expected {expected[n]}" for n in bad)
    return (
        f"cycle {cycle}: {diffs} (valid expected {expected['valid']}); {which} "
        f"{_job_text(job)}; inputs at this edge {stim[cycle]}"
    )


def _job_text(job: Job | None) -> str:
    if job is None:
        return "none since reset"
    ops = ", ".join(f"{k}={v}" for k, v in job.operands.items())
    write = ", with an operand write in the start cycle" if job.write_at_start else ""
    return f"with inputs {ops} (started at cycle {job.started_at - 1}{write})"
