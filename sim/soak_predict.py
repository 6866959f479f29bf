# SPDX-License-Identifier: Apache-2.0
"""The soak's prediction and vector file as numba kernels over numpy integer arrays.

The soak (sim/soak.py) needs millions of cycles a second; a ``ProtocolModel.step`` per cycle
in Python (sim/protocol.py) gives about a hundred thousand.  This module does its work over
the arrays of a ``soak_stimulus.Stimulus``:

* ``predict(cfg, stim)``: the protocol as one kernel (``_protocol_kernel``: writes and starts
  ignored while busy, a start taking the operand registers as they were before the edge's
  writes, a reset aborting the job and clearing the registers, nothing known before the first
  reset), then the results of every accepted job from the golden model's own calls over all
  jobs at once (``divider.divide_many``, ``gouraud.lane_pixel``, ``specular.shade_lines``),
  with each job's busy cycles and valid offsets from the unit's ``cycles`` (``timing``, checked
  against ``units.expect`` when it is built);
* ``columns``, ``Prediction.table``: the results as one int64 row each, which the vector
  file's kernel (sim/soak_file.py) writes.

``ProtocolModel`` stays the readable reference: tests/test_soak_fast.py checks that
``Prediction.outputs`` equals its ``step`` in every cycle, in both RESET_ALL modes, and that the
file (sim/soak_file.py) equals ``write_vectors`` of its predictions byte for byte, for every
soak configuration.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numba import njit

from model.units import brdf, divider, gouraud, specular
from model.units.brdf import FixedConfig
from model.units.brdf import lines as brdf_lines
from model.units.divider import DividerConfig
from model.units.gouraud import GouraudConfig
from model.units.specular import N_MAX, SpecularConfig
from sim import units
from sim.protocol import Job, Stats, UnitSpec
from sim.soak_stimulus import MAX_BITS, Stimulus

# The counters of ``Stats``, in the order the protocol kernel keeps them.
STATS = (
    "jobs_started",
    "jobs_completed",
    "jobs_aborted",
    "results_compared",
    "writes_ignored",
    "starts_ignored",
    "writes_at_start",
    "resets",
    "back_to_back",
    "cycles",
)


# ---------------------------------------------------------------------- timing and results
@dataclass(frozen=True)
class Timing:
    """A job's timing from one operand's value (``key``: its index): ``busy`` cycles, then
    ``count`` results at the consecutive offsets from ``first`` on, indexed by that value."""

    key: int
    busy: np.ndarray
    first: np.ndarray
    count: np.ndarray


def _keys_to_check(n: int) -> list[int]:
    if n <= 128:
        return list(range(n))
    return sorted({*range(64), *range(n - 16, n), *range(0, n, max(1, n // 48))})


@functools.cache
def timing(cfg: units.UnitConfig) -> Timing:
    """The unit's ``Timing`` from its ``cycles``; each of a sample of values (every one up to
    128 of them) checked against the job ``units.expect`` makes (busy cycles, valid offsets)."""
    spec = units.spec(cfg)
    names = [p.name for p in spec.operands]
    if isinstance(cfg, DividerConfig):
        key = names.index("k")
        keys = np.arange(cfg.k_max + 1)
        busy = np.asarray(divider.cycles(keys, cfg), dtype=np.int64)
        first, count = busy.copy(), np.ones_like(busy)
    elif isinstance(cfg, GouraudConfig):
        key = names.index("len")
        keys = np.arange(cfg.len_max + 1)
        busy = np.asarray(gouraud.cycles(keys, cfg), dtype=np.int64)
        first, count = np.ones_like(busy), busy.copy()
    elif isinstance(cfg, SpecularConfig | FixedConfig):
        # the BRDF unit (a FixedConfig) runs the specular unit's line: fill, then l + 1 results
        key = names.index("len")
        model, fmt = (specular, cfg) if isinstance(cfg, SpecularConfig) else (brdf, cfg.angle)
        keys = np.arange(fmt.len_max + 1)
        busy = np.asarray(model.cycles(keys, cfg), dtype=np.int64)
        first, count = busy - keys, keys + 1
    else:
        raise TypeError(f"no unit has a configuration of type {type(cfg).__name__}")
    expect = units.expect(cfg)
    for value in _keys_to_check(keys.size):
        job = expect({**spec.reset_operands, names[key]: value})
        offsets = list(range(int(first[value]), int(first[value] + count[value])))
        if job.busy_cycles != busy[value] or job.valid_offsets != offsets:
            raise AssertionError(
                f"{spec.toplevel}: the soak's timing of {names[key]} = {value} (busy "
                f"{busy[value]}, valid {offsets}) differs from the model's job (busy "
                f"{job.busy_cycles}, valid {job.valid_offsets})"
            )
    return Timing(key, busy, first.astype(np.int64), count.astype(np.int64))


@dataclass(frozen=True)
class Column:
    """One column of a result row: a port, or a lane of a wide port (MSB-first order)."""

    port: str
    width: int
    kind: str


@functools.cache
def unit_spec(cfg: units.UnitConfig) -> UnitSpec:
    """``units.spec(cfg)``, built once per configuration."""
    return units.spec(cfg)


@functools.cache
def columns(cfg: units.UnitConfig) -> tuple[Column, ...]:
    """The result row's columns in the order of the response word after busy and valid; the
    Gouraud unit's ``pixels`` as its P lanes, lane P - 1 first (lane 0 is the low bits)."""
    out = []
    for p in units.spec(cfg).outputs:
        if isinstance(cfg, GouraudConfig) and p.name == "pixels":
            out += [Column(p.name, cfg.i_int, p.kind) for _ in range(cfg.p)]
        else:
            out.append(Column(p.name, p.width, p.kind))
    for c in out:
        if c.width > MAX_BITS:
            raise ValueError(f"output {c.port} is {c.width} bits: the soak packs up to {MAX_BITS}")
    return tuple(out)


@njit(cache=True)
def _gouraud_kernel(
    i0: np.ndarray, di: np.ndarray, length: np.ndarray, base: np.ndarray, p: int, bias: int,
    frac: int, out_max: int, table: np.ndarray,
) -> None:  # fmt: skip
    """Each job's segments: P lane pixels (closed form, ``gouraud.lane_pixel``), the lane mask
    and ``last``, row by row (lane P - 1 in column 0)."""
    for j in range(i0.size):
        nseg = base[j + 1] - base[j]
        for s in range(nseg):
            row = base[j] + s
            mask = 0
            for lane in range(p):
                x = s * p + lane
                table[row, p - 1 - lane] = gouraud.lane_pixel(i0[j], di[j], x, bias, frac, out_max)
                if x < length[j]:
                    mask |= 1 << lane
            table[row, p] = mask
            table[row, p + 1] = 1 if s == nseg - 1 else 0


@functools.cache
def _n_valid(cfg: SpecularConfig) -> np.ndarray:
    return np.array([specular.n_valid(n, cfg) for n in range(1 << units.N_WIDTH)])


def _brdf_results(cfg: FixedConfig, job_ops: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """The BRDF unit's (intensity, n_err) rows of every job: its lines through
    ``brdf.lines.shade_lines`` (row for row ``brdf.unit_line``), n_err on every pixel of a job
    whose n is outside 1..1000."""
    c, dz, z0, n, length = (np.ascontiguousarray(job_ops[:, i]) for i in range(5))
    pixels = brdf_lines.shade_lines(c, dz, z0, n, length, cfg).pixels
    bad = ((n < 1) | (n > N_MAX)).astype(np.int64)
    return np.stack([pixels, np.repeat(bad, counts)], axis=1)


def results(cfg: units.UnitConfig, job_ops: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(``base``, ``table``): job j's results are rows ``base[j] : base[j + 1]`` of ``table``,
    one column per ``columns(cfg)``, from the golden model for all jobs in one call."""
    t = timing(cfg)
    counts = t.count[job_ops[:, t.key]] if job_ops.size else np.zeros(0, dtype=np.int64)
    base = np.zeros(len(job_ops) + 1, dtype=np.int64)
    np.cumsum(counts, out=base[1:])
    total = int(base[-1])
    if isinstance(cfg, DividerConfig):
        a, k = job_ops[:, 0], job_ops[:, 1]
        q = np.zeros(len(job_ops), dtype=np.int64)
        nz = k > 0
        if nz.any():
            q[nz] = divider.divide_many(a[nz], k[nz], cfg)[0]
        return base, np.stack([q, (k == 0).astype(np.int64)], axis=1)
    if isinstance(cfg, GouraudConfig):
        table = np.empty((total, cfg.p + 2), dtype=np.int64)  # the kernel writes every cell
        i0, di, length = (np.ascontiguousarray(job_ops[:, i]) for i in range(3))
        _gouraud_kernel(i0, di, length, base, cfg.p, cfg.round_bias, cfg.i_frac, cfg.out_max, table)
        return base, table
    if isinstance(cfg, FixedConfig):
        return base, _brdf_results(cfg, job_ops, counts)
    c, dz, z0, n, length = (np.ascontiguousarray(job_ops[:, i]) for i in range(5))
    ok = _n_valid(cfg)[n] if len(n) else np.zeros(0, dtype=bool)
    values = np.zeros(total, dtype=np.int64)
    if ok.any():
        at = base[:-1][ok]
        specular.shade_lines(c[ok], dz[ok], z0[ok], n[ok], length[ok], cfg, out=values, at=at)
    n_err = np.repeat((~ok).astype(np.int64), counts)
    return base, np.stack([values, n_err], axis=1)


# ---------------------------------------------------------------------- the protocol
@njit(cache=True)
def _protocol_kernel(
    rst_n: np.ndarray, start: np.ndarray, we: np.ndarray, value: np.ndarray,
    reset_values: np.ndarray, key: int, busy_of: np.ndarray, first_of: np.ndarray,
    count_of: np.ndarray, busy_out: np.ndarray, valid_out: np.ndarray, held_out: np.ndarray,
    seq_out: np.ndarray, last_out: np.ndarray, job_ops: np.ndarray, job_start: np.ndarray,
    job_write: np.ndarray, stats: np.ndarray,
) -> int:  # fmt: skip
    """``ProtocolModel.step`` over every cycle.  Per cycle: busy and valid (-1: nothing known
    before the first reset), the job whose result ``seq_out`` the held outputs show (-1: none
    since reset, -2: nothing known) and the latest accepted job (-1: none since reset); per
    job its operand registers at the start, the start edge (the cycle count) and whether a
    write came with it; ``stats`` as ``STATS``.  Returns the number of jobs."""
    nops = reset_values.size
    shadow = reset_values.copy()
    known = False
    busy = 0
    job = -1
    offset = seen = job_busy = job_first = job_count = 0
    held = -2
    held_seq = 0
    last = -1
    completed_at = -2
    jobs = 0
    for c in range(rst_n.size):
        edge = c + 1
        stats[9] += 1
        if rst_n[c] == 0:
            if job >= 0:
                stats[2] += 1
            job = last = held = -1
            busy = 0
            shadow[:] = reset_values
            stats[7] += 1
            known = True
            busy_out[c] = valid_out[c] = 0
            held_out[c] = last_out[c] = -1
            continue
        if not known:
            busy_out[c] = valid_out[c] = -1
            held_out[c] = -2
            last_out[c] = -1
            continue
        writes = 0
        for p in range(nops):
            writes += we[c, p]
        new_job = False
        if busy:
            stats[4] += writes
            stats[5] += start[c]
        else:
            if start[c]:
                job = last = jobs
                jobs += 1
                job_ops[job, :] = shadow
                job_start[job] = edge
                job_write[job] = 1 if writes else 0
                v = shadow[key]
                job_busy, job_first, job_count = busy_of[v], first_of[v], count_of[v]
                offset = seen = 0
                new_job = True
                stats[0] += 1
                if writes:
                    stats[6] += 1
                if completed_at == edge - 1:
                    stats[8] += 1
            for p in range(nops):
                if we[c, p]:
                    shadow[p] = value[c, p]
        b = v_out = 0
        if job >= 0:
            if not new_job:
                offset += 1
            if seen < job_count and offset == job_first + seen:
                held, held_seq = job, seen
                seen += 1
                stats[3] += 1
                v_out = 1
            if offset < job_busy:
                b = 1
            else:
                stats[1] += 1
                completed_at = edge
                job = -1
        busy = b
        busy_out[c], valid_out[c] = b, v_out
        held_out[c], seq_out[c], last_out[c] = held, held_seq, last
    return jobs


@dataclass(frozen=True)
class Prediction:
    """What ``predict`` knows of every cycle (see ``_protocol_kernel``), every job's operands
    and results, and the stimulus' ``Stats``."""

    cfg: units.UnitConfig
    busy: np.ndarray
    valid: np.ndarray
    held: np.ndarray
    seq: np.ndarray
    last: np.ndarray
    job_ops: np.ndarray
    job_start: np.ndarray
    job_write: np.ndarray
    base: np.ndarray
    table: np.ndarray
    stats: Stats

    def _result(self, row: int) -> dict[str, int]:
        out: dict[str, int] = {}
        cols = columns(self.cfg)
        for col, value in zip(cols, self.table[row].tolist(), strict=True):
            out[col.port] = (out[col.port] << col.width) | value if col.port in out else value
        return out

    def outputs(self, cycle: int, reset_all: bool = False) -> dict[str, int | None]:
        """The outputs expected after ``cycle``'s edge, as ``ProtocolModel.step`` returns them
        (``None``: undefined)."""
        spec = unit_spec(self.cfg)
        if self.busy[cycle] < 0:
            return {"busy": None, "valid": None, **{p.name: None for p in spec.outputs}}
        out: dict[str, int | None] = {"busy": int(self.busy[cycle])}
        out["valid"] = valid = int(self.valid[cycle])
        job = int(self.held[cycle])
        if job < 0:
            for p in spec.outputs:
                out[p.name] = None if p.kind == "data" and not reset_all else 0
            return out
        result = self._result(int(self.base[job] + self.seq[cycle]))
        for p in spec.outputs:
            out[p.name] = 0 if p.kind == "strobe" and not valid else result[p.name]
        return out

    def job(self, j: int) -> Job | None:
        """Job ``j`` as ``units.expect`` describes it, with its start edge; -1 gives None."""
        if j < 0:
            return None
        t = timing(self.cfg)
        names = [p.name for p in unit_spec(self.cfg).operands]
        key = int(self.job_ops[j, t.key])
        first, count = int(t.first[key]), int(t.count[key])
        rows = range(int(self.base[j]), int(self.base[j + 1]))
        return Job(
            operands=dict(zip(names, self.job_ops[j].tolist(), strict=True)),
            results=[self._result(r) for r in rows],
            busy_cycles=int(t.busy[key]),
            valid_offsets=list(range(first, first + count)),
            started_at=int(self.job_start[j]),
            write_at_start=bool(self.job_write[j]),
        )

    def job_at(self, cycle: int) -> Job | None:
        """The latest accepted job at ``cycle`` (``ProtocolModel.last_job``)."""
        return self.job(int(self.last[cycle]))

    def result_job_at(self, cycle: int) -> Job | None:
        """The job whose result the held outputs show at ``cycle``."""
        return self.job(int(self.held[cycle]))


def predict(cfg: units.UnitConfig, stim: Stimulus) -> Prediction:
    """Every output of every cycle of ``stim``, as ``ProtocolModel`` predicts it."""
    spec = units.spec(cfg)
    t = timing(cfg)
    n = len(stim)
    nops = len(spec.operands)
    bound = int(np.count_nonzero(stim.start)) + 1
    busy, valid = np.zeros(n, dtype=np.int8), np.zeros(n, dtype=np.int8)
    held, seq, last = (np.zeros(n, dtype=np.int32) for _ in range(3))
    job_ops = np.zeros((bound, nops), dtype=np.int64)
    job_start = np.zeros(bound, dtype=np.int64)
    job_write = np.zeros(bound, dtype=np.uint8)
    counters = np.zeros(len(STATS), dtype=np.int64)
    reset_values = np.array([p.reset for p in spec.operands], dtype=np.int64)
    jobs = _protocol_kernel(
        stim.rst_n, stim.start, stim.we, stim.value, reset_values, t.key, t.busy, t.first,
        t.count, busy, valid, held, seq, last, job_ops, job_start, job_write, counters,
    )  # fmt: skip
    job_ops = job_ops[:jobs]
    base, table = results(cfg, job_ops)
    stats = Stats(**dict(zip(STATS, counters.tolist(), strict=True)))
    return Prediction(
        cfg, busy, valid, held, seq, last, job_ops, job_start[:jobs], job_write[:jobs], base,
        table, stats,
    )  # fmt: skip
