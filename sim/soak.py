# SPDX-License-Identifier: Apache-2.0
"""Constrained-random soak: random strobes, start timing and resets, every output every cycle.

``stimulus(cfg, cycles, seed)`` draws what a careless host could do to a unit, cycle by cycle:
each write strobe and ``start`` at random, operand values from the extremes, values next to 0
(so a register crosses 0 from one job to the next, e.g. the divider's k), powers of two and
uniform ones, writes in the start cycle and in every busy cycle, and a short random reset now
and then.  The protocol model (sim/protocol.py) predicts every output in every cycle.

``run_soak(cfg, cycles, seed)`` writes the stimulus and the prediction as ``$readmemh`` files
and replays them through the unit in a plain Verilog bench (sim/vectors/tb_<unit>.v, no
Python in the loop; one instance with RESET_ALL = 0 and one with RESET_ALL = 1), which compares
every output with the prediction in every cycle.  The same files, for a fixed seed, are the
committed vector sets under sim/vectors/<set>/ (sim/vector_sets.py, ``make vectors``).  Each
mismatch comes back decoded: the cycle, the output, the value, the model's value, and the
operands of the job that reproduce it, with the seed that replays the whole run
(``SOAK_SEED``).  The cocotb benches drive the same stimulus through their monitor.
"""

from __future__ import annotations

import random
import re
import shutil
import subprocess
from dataclasses import dataclass, field
from importlib.resources import files
from pathlib import Path

from model.units.specular import N_MAX, SpecularConfig
from sim import units
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


def predict(cfg: units.UnitConfig, stim: list[Inputs]) -> Prediction:
    model = ProtocolModel(units.spec(cfg), units.expect(cfg))
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


def write_vectors(
    spec: UnitSpec, stim: list[Inputs], expected: list[dict[str, int | None]], folder: Path
) -> dict[str, Path]:
    """stim.hex, expect.hex and mask.hex (one word per cycle) in ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    sf, of = stim_fields(spec), out_fields(spec)
    sd, od = -(-width(sf) // 4), -(-width(of) // 4)
    paths = {k: folder / f"{k}.hex" for k in ("stim", "expect", "mask")}
    with (
        paths["stim"].open("w") as fs,
        paths["expect"].open("w") as fe,
        paths["mask"].open("w") as fm,
    ):
        for inputs, outputs in zip(stim, expected, strict=True):
            fs.write(f"{pack(sf, inputs)[0]:0{sd}x}\n")
            word, mask = pack(of, outputs)
            fe.write(f"{word:0{od}x}\n")
            fm.write(f"{mask:0{od}x}\n")
    return paths


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
DONE = re.compile(r"^VECTORS (\d+) cycles (\d+) mismatches$", re.M)


def iverilog_parameters(top: str, params: dict[str, object]) -> list[str]:
    args = []
    for key, value in params.items():
        shown = f'"{value}"' if isinstance(value, str | Path) else str(int(value))
        args.append(f"-P{top}.{key}={shown}")
    return args


def run_soak(
    cfg: units.UnitConfig,
    cycles: int,
    seed: int,
    build_dir: Path,
    parameters: dict[str, object],
    rtl: Path | None = None,
) -> SoakResult:
    """Replay ``cycles`` random cycles through the RTL under Icarus; decode every mismatch.

    ``parameters`` are the unit's Verilog parameters (sim.runner.hdl_parameters); ``rtl``
    replaces ``rtl/<unit>.v`` (a saved mutant, to show the soak can fail).
    """
    spec = units.spec(cfg)
    stim = stimulus(cfg, cycles, seed)
    pred = predict(cfg, stim)
    files = write_vectors(spec, stim, pred.outputs, build_dir)
    top = f"tb_{spec.toplevel}"
    params = {
        **parameters,
        "CYCLES": cycles,
        "STIM_FILE": str(files["stim"]),
        "EXPECT_FILE": str(files["expect"]),
        "MASK_FILE": str(files["mask"]),
    }
    iverilog = shutil.which("iverilog")
    if iverilog is None:
        raise RuntimeError("iverilog is not on PATH: install it with 'apt-get install iverilog'")
    vvp = build_dir / "soak.vvp"
    sources = [VECTOR_DIR / f"{top}.v", rtl or RTL_DIR / f"{spec.toplevel}.v"]
    cmd = [iverilog, "-g2005", "-o", str(vvp), "-s", top, f"-I{VECTOR_DIR}"]
    cmd += iverilog_parameters(top, params) + [str(s) for s in sources]
    built = subprocess.run(cmd, capture_output=True, text=True, cwd=RTL_DIR)
    if built.returncode != 0:
        raise RuntimeError(f"iverilog failed on {top}:\n{built.stdout}{built.stderr}")
    ran = subprocess.run(
        ["vvp", "-n", str(vvp)], capture_output=True, text=True, cwd=RTL_DIR, timeout=600
    )
    log = ran.stdout + ran.stderr
    done = DONE.search(log)
    # The bench ends with a non-zero exit status after its count when anything mismatched.
    failed_clean = done is not None and int(done.group(2)) > 0
    if (ran.returncode != 0 and not failed_clean) or done is None or int(done.group(1)) != cycles:
        raise RuntimeError(
            f"{top} did not finish its {cycles} cycles (exit {ran.returncode}):\n{log}"
        )
    result = SoakResult(spec.toplevel, seed, cycles, pred.stats, log=log)
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
